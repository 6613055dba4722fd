#include "core/prepare/envelope_reduce.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <vector>

namespace spheremap {
namespace {

// Garland and Heckbert's quadric: the sum of squared distances to a set of planes.
struct Quadric {
  double q[10] = {};  // xx xy xz xw yy yz yw zz zw ww
  void add_plane(const Vec3& n, double d, double weight) {
    const double a = n.x, b = n.y, c = n.z;
    const double terms[10] = {a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d};
    for (int k = 0; k < 10; ++k) q[k] += weight * terms[k];
  }
  Quadric operator+(const Quadric& o) const {
    Quadric r;
    for (int k = 0; k < 10; ++k) r.q[k] = q[k] + o.q[k];
    return r;
  }
  double error(const Vec3& p) const {
    const double x = p.x, y = p.y, z = p.z;
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
           2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
  }
  // The point of least error when the system is well conditioned, else the best of a, b
  // and their midpoint.
  Vec3 best(const Vec3& a, const Vec3& b) const {
    const double m00 = q[0], m01 = q[1], m02 = q[2], m11 = q[4], m12 = q[5], m22 = q[7];
    const double c00 = m11 * m22 - m12 * m12, c01 = m02 * m12 - m01 * m22,
                 c02 = m01 * m12 - m02 * m11;
    const double det = m00 * c00 + m01 * c01 + m02 * c02;
    const double scale = std::abs(m00) + std::abs(m11) + std::abs(m22);
    if (std::abs(det) > 1e-9 * scale * scale * scale) {
      const double c11 = m00 * m22 - m02 * m02, c12 = m01 * m02 - m00 * m12,
                   c22 = m00 * m11 - m01 * m01;
      const Vec3 r{-q[3], -q[6], -q[8]};
      const Vec3 x{(c00 * r.x + c01 * r.y + c02 * r.z) / det,
                   (c01 * r.x + c11 * r.y + c12 * r.z) / det,
                   (c02 * r.x + c12 * r.y + c22 * r.z) / det};
      // Only near the edge: far solutions come from nearly parallel planes.
      if (squared_norm(x - (a + b) * 0.5) <= squared_norm(b - a)) return x;
    }
    const Vec3 m = (a + b) * 0.5;
    const double ea = error(a), eb = error(b), em = error(m);
    return em <= ea && em <= eb ? m : (ea <= eb ? a : b);
  }
};

struct Candidate {
  double cost;
  uint32_t u, v, version_u, version_v;
  bool operator>(const Candidate& o) const { return cost > o.cost; }
};

class Reducer {
 public:
  explicit Reducer(const PolygonMesh& mesh)
      : positions_(mesh.positions), around_(mesh.vertex_count()), version_(mesh.vertex_count(), 0) {
    triangles_.resize(mesh.face_count());
    for (size_t f = 0; f < mesh.face_count(); ++f) {
      const auto c = mesh.face(f);
      triangles_[f] = {c[0], c[1], c[2]};
      for (uint32_t v : triangles_[f]) around_[v].push_back(uint32_t(f));
    }
    alive_.assign(triangles_.size(), 1);
    faces_ = triangles_.size();
    quadric_.resize(positions_.size());
    for (const Triangle& t : triangles_) {
      const Vec3 n =
          cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]);
      const double area2 = norm(n);
      if (!(area2 > 0)) continue;
      const Vec3 unit = n * (1 / area2);
      for (uint32_t v : t) quadric_[v].add_plane(unit, -dot(unit, positions_[t[0]]), area2);
    }
    queue_all();
  }

  // Edges refused once (link condition, shape) are not queued again when their
  // neighbourhood changes; a further pass over every edge left takes them up.
  void run(size_t target, StopCheck& stop) {
    for (int pass = 0; pass < 4 && faces_ > target; ++pass) {
      if (pass > 0) queue_all();
      const size_t before = collapses_;
      while (faces_ > target && faces_ > 4 && !queue_.empty()) {
        const Candidate c = queue_.top();
        queue_.pop();
        stop.tick();
        if (c.version_u != version_[c.u] || c.version_v != version_[c.v]) continue;
        collapse(c.u, c.v);
      }
      if (collapses_ == before) break;
    }
  }

  void queue_all() {
    queue_ = {};
    for (size_t f = 0; f < triangles_.size(); ++f)
      if (alive_[f])
        for (size_t k = 0; k < 3; ++k) {
          const uint32_t a = triangles_[f][k], b = triangles_[f][(k + 1) % 3];
          if (a < b) push(a, b);
        }
  }

  PolygonMesh result() const {
    PolygonMesh out;
    std::vector<uint32_t> id(positions_.size(), UINT32_MAX);
    for (size_t f = 0; f < triangles_.size(); ++f) {
      if (!alive_[f]) continue;
      std::array<uint32_t, 3> corners{};
      for (size_t k = 0; k < 3; ++k) {
        uint32_t& n = id[triangles_[f][k]];
        if (n == UINT32_MAX)
          n = uint32_t(out.positions.size()), out.positions.push_back(positions_[triangles_[f][k]]);
        corners[k] = n;
      }
      out.add_face(corners);
    }
    return out;
  }

 private:
  // Cost: the quadric error at the collapse's point plus a little of the edge's length, so
  // flat regions still collapse shortest first.
  void push(uint32_t a, uint32_t b) {
    const Quadric q = quadric_[a] + quadric_[b];
    const Vec3 p = q.best(positions_[a], positions_[b]);
    const double cost =
        std::max(0.0, q.error(p)) + 1e-3 * squared_norm(positions_[a] - positions_[b]);
    queue_.push({cost, a, b, version_[a], version_[b]});
  }

  // The vertices sharing a triangle with v, sorted, into `out`.
  void neighbours(uint32_t v, std::vector<uint32_t>& out) const {
    out.clear();
    for (uint32_t f : around_[v])
      for (uint32_t w : triangles_[f])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }
  size_t degree(uint32_t v) {
    neighbours(v, scratch_);
    return scratch_.size();
  }

  // Whether the triangles of `v` not containing `other` keep their shape with v at p.
  bool keeps_shape(uint32_t v, uint32_t other, const Vec3& p) const {
    for (uint32_t f : around_[v]) {
      const Triangle& t = triangles_[f];
      if (t[0] == other || t[1] == other || t[2] == other) continue;
      std::array<Vec3, 3> before{}, after{};
      for (size_t k = 0; k < 3; ++k)
        before[k] = positions_[t[k]], after[k] = t[k] == v ? p : before[k];
      const Vec3 nb = cross(before[1] - before[0], before[2] - before[0]);
      const Vec3 na = cross(after[1] - after[0], after[2] - after[0]);
      const double longest =
          std::max({squared_norm(after[1] - after[0]), squared_norm(after[2] - after[1]),
                    squared_norm(after[0] - after[2])});
      if (!(norm(na) > 1e-6 * longest) || !(dot(nb, na) > 0.5 * norm(nb) * norm(na))) return false;
    }
    return true;
  }

  void collapse(uint32_t u, uint32_t v) {
    neighbours(u, nu_);
    neighbours(v, nv_);
    if (!std::binary_search(nu_.begin(), nu_.end(), v)) return;
    common_.clear();
    std::set_intersection(nu_.begin(), nu_.end(), nv_.begin(), nv_.end(),
                          std::back_inserter(common_));
    // The link condition, and no neighbour of the two ends left with 2 neighbours.
    if (common_.size() != 2 || nu_.size() + nv_.size() - 4 < 3) return;
    for (uint32_t w : common_)
      if (degree(w) <= 3) return;
    const Quadric q = quadric_[u] + quadric_[v];
    const Vec3 p = q.best(positions_[u], positions_[v]);
    if (!keeps_shape(u, v, p) || !keeps_shape(v, u, p)) return;
    for (uint32_t f : around_[v]) {
      Triangle& t = triangles_[f];
      if (t[0] == u || t[1] == u || t[2] == u) {  // one of the two on the edge: gone
        alive_[f] = 0, --faces_;
        for (uint32_t w : t)
          if (w != v) std::erase(around_[w], f);
        continue;
      }
      for (uint32_t& w : t)
        if (w == v) w = u;
      around_[u].push_back(f);
    }
    around_[v].clear();
    positions_[u] = p;
    quadric_[u] = q;
    ++version_[u], ++version_[v];  // their queued edges are stale; u's are queued again
    ++collapses_;
    neighbours(u, nu_);
    for (uint32_t w : nu_) push(std::min(u, w), std::max(u, w));
  }

  std::vector<Vec3> positions_;
  std::vector<Triangle> triangles_;
  std::vector<uint8_t> alive_;
  std::vector<std::vector<uint32_t>> around_;
  std::vector<uint32_t> version_;
  std::vector<Quadric> quadric_;
  size_t faces_ = 0, collapses_ = 0;
  std::vector<uint32_t> nu_, nv_, common_, scratch_;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue_;
};

}  // namespace

PolygonMesh reduce_surface(const PolygonMesh& mesh, size_t target_faces, StopCheck& stop) {
  if (mesh.face_count() <= target_faces) return mesh;
  Reducer reducer(mesh);
  reducer.run(target_faces, stop);
  return reducer.result();
}

}  // namespace spheremap
