#include "core/outputs/texcoords.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace spheremap {
namespace {

// A corner of a clipped polygon: the chord point (not normalized), the surface point,
// and where it lies on the input triangle, so that neighbours share the points they
// make on a common edge.
struct Corner {
  Vec3 chord, surface;
  uint32_t a = UINT32_MAX, b = UINT32_MAX;  // input vertex (a, b = a), edge (a < b), or none
};

bool on_common_edge(const Corner& p, const Corner& q, uint32_t& u, uint32_t& w) {
  if (p.a == UINT32_MAX || q.a == UINT32_MAX) return false;
  uint32_t ids[4] = {p.a, p.b, q.a, q.b};
  std::sort(ids, ids + 4);
  const uint32_t* end = std::unique(ids, ids + 4);
  if (end - ids != 2) return false;
  u = ids[0], w = ids[1];
  return true;
}

double sign_of(double v) {
  return v < 0 ? -1.0 : 1.0;
}

// The unfolding of a point of the closed quadrant (sx, sy): on a cut (x or y = 0, z < 0)
// the side is the quadrant's, so each side gets its own copy.
Vec2 encode_in_quadrant(const Vec3& p, double sx, double sy) {
  const double l1 = std::abs(p.x) + std::abs(p.y) + std::abs(p.z);
  const double x = p.x / l1, y = p.y / l1;
  if (p.z >= 0) return {x, y};
  return {(1 - std::abs(y)) * sx, (1 - std::abs(x)) * sy};
}

class Clipper {
 public:
  Clipper(std::span<const Vec3> surface, std::span<const Vec3> sphere, UvMesh& out)
      : surface_(surface), sphere_(sphere), out_(out) {}

  void add(const Triangle& t) {
    std::vector<Corner> polygon;
    for (uint32_t v : t) polygon.push_back({point(v), surface_[v], v, v});
    const Vec3 a = point(t[0]), b = point(t[1]), c = point(t[2]);
    auto same_side = [&](int axis) {
      return sign_of(b[axis]) == sign_of(a[axis]) && sign_of(c[axis]) == sign_of(a[axis]);
    };
    if (same_side(0) && same_side(1) && same_side(2)) {
      emit(polygon, sign_of(a.x), sign_of(a.y));
      return;
    }
    // Within an octant the unfolding is a central projection onto an octahedron face (then
    // an affine fold): straight, orientation-preserving. Across octants it bends, and a
    // thin triangle's straight UV triangle could flip, so every octant gets its own piece.
    ++out_.split_triangles;
    for (double sx : {1.0, -1.0}) {
      const std::vector<Corner> x_part = clip(polygon, 0, sx);
      for (double sy : {1.0, -1.0}) {
        const std::vector<Corner> xy_part = clip(x_part, 1, sy);
        for (double sz : {1.0, -1.0}) emit(clip(xy_part, 2, sz), sx, sy);
      }
    }
  }

 private:
  // The sphere point with coordinates within rounding of a plane put on it: maps of
  // symmetric meshes hold vertices at x = 1e-16, and clipping there makes slivers.
  Vec3 point(uint32_t v) const {
    Vec3 p = sphere_[v];
    for (double* c : {&p.x, &p.y, &p.z})
      if (std::abs(*c) < 1e-12) *c = 0;
    return p;
  }

  // Sutherland-Hodgman: the part of the polygon where sign * coordinate[axis] >= 0.
  std::vector<Corner> clip(const std::vector<Corner>& polygon, int axis, double sign) {
    std::vector<Corner> out;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const Corner& p = polygon[i];
      const Corner& q = polygon[(i + 1) % polygon.size()];
      const double dp = sign * p.chord[axis], dq = sign * q.chord[axis];
      if (dp >= 0) out.push_back(p);
      if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) out.push_back(crossing(p, q, axis));
    }
    return out;
  }

  // Where the segment pq meets the plane coordinate[axis] = 0. On an input edge the point
  // is computed from the edge's ends in a fixed order, so both triangles get the same one.
  Corner crossing(const Corner& p, const Corner& q, int axis) {
    uint32_t u, w;
    Corner from = p, to = q;
    Corner out;
    if (on_common_edge(p, q, u, w)) {
      from = {point(u), surface_[u], u, u};
      to = {point(w), surface_[w], w, w};
      out.a = u, out.b = w;
    }
    const double t = from.chord[axis] / (from.chord[axis] - to.chord[axis]);
    out.chord = from.chord + (to.chord - from.chord) * t;
    out.surface = from.surface + (to.surface - from.surface) * t;
    (axis == 0 ? out.chord.x : axis == 1 ? out.chord.y : out.chord.z) = 0;  // exactly on it
    return out;
  }

  uint32_t vertex(const Corner& c, double sx, double sy) {
    const Vec2 uv = encode_in_quadrant(c.chord, sx, sy);
    // Same point and same (u, v): one vertex. Points made inside a triangle are its own.
    const auto key = std::make_tuple(c.a, c.b, uv[0], uv[1]);
    if (c.a != UINT32_MAX) {
      const auto found = vertices_.find(key);
      if (found != vertices_.end()) return found->second;
    }
    const uint32_t id = static_cast<uint32_t>(out_.positions.size());
    out_.positions.push_back(c.surface);
    out_.square.push_back(uv);
    if (c.a != UINT32_MAX) vertices_[key] = id;
    if (c.a == c.b) inputs_used_.insert(c.a);
    return id;
  }

  void emit(const std::vector<Corner>& polygon, double sx, double sy) {
    if (polygon.size() < 3) return;
    std::vector<uint32_t> ids;
    for (const Corner& c : polygon) ids.push_back(vertex(c, sx, sy));
    for (size_t k = 1; k + 1 < ids.size(); ++k) {
      const Triangle t = {ids[0], ids[k], ids[k + 1]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // a corner on the cut
      out_.triangles.push_back(t);
    }
  }

  std::span<const Vec3> surface_, sphere_;
  UvMesh& out_;
  std::map<std::tuple<uint32_t, uint32_t, double, double>, uint32_t> vertices_;
  std::set<uint32_t> inputs_used_;

 public:
  size_t inputs_used() const { return inputs_used_.size(); }
};

}  // namespace

UvMesh octahedral_texcoords(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                            std::span<const Triangle> triangles) {
  UvMesh out;
  Clipper clipper(surface, sphere, out);
  for (const Triangle& t : triangles) clipper.add(t);
  out.seam_vertices = out.positions.size() - clipper.inputs_used();
  for (const Triangle& t : out.triangles) {
    const Vec2 &a = out.square[t[0]], &b = out.square[t[1]], &c = out.square[t[2]];
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const double longest =
        std::max({(b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]),
                  (c[0] - a[0]) * (c[0] - a[0]) + (c[1] - a[1]) * (c[1] - a[1]),
                  (c[0] - b[0]) * (c[0] - b[0]) + (c[1] - b[1]) * (c[1] - b[1])});
    // Collinear within rounding (a clipped sliver along a cut): neither way round.
    if (std::abs(area) <= 1e-15 * longest)
      ++out.degenerate;
    else if (area < 0)
      ++out.flipped;
  }
  return out;
}

UvStretch uv_stretch(std::span<const Vec3> input_surface, std::span<const Vec2> square,
                     std::span<const Triangle> triangles) {
  // Stretch is a ratio: taken on the surface centred and scaled, so that its sums of
  // areas neither overflow nor underflow in extreme units.
  const std::vector<Vec3> surface = centered_and_scaled(input_surface);
  double surface_total = 0, square_total = 0;
  for (const Triangle& t : triangles) {
    surface_total +=
        0.5 * norm(cross(surface[t[1]] - surface[t[0]], surface[t[2]] - surface[t[0]]));
    const Vec2 &a = square[t[0]], &b = square[t[1]], &c = square[t[2]];
    square_total += 0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
  }
  UvStretch out;
  if (!(surface_total > 0 && square_total > 0)) return out;
  const double scale = std::sqrt(square_total / surface_total);  // domain scaled to the area
  double sum = 0, weight = 0;
  for (const Triangle& t : triangles) {
    const Vec2 &a = square[t[0]], &b = square[t[1]], &c = square[t[2]];
    const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (area2 == 0) continue;
    const Vec3 &p = surface[t[0]], &q = surface[t[1]], &r = surface[t[2]];
    // Partial derivatives of the surface point along u and v (Sander et al., eq. 2).
    const Vec3 ds = (p * (b[1] - c[1]) + q * (c[1] - a[1]) + r * (a[1] - b[1])) * (1 / area2);
    const Vec3 dt = (p * (c[0] - b[0]) + q * (a[0] - c[0]) + r * (b[0] - a[0])) * (1 / area2);
    const double ea = dot(ds, ds), eb = dot(ds, dt), ec = dot(dt, dt);
    const double big =
        std::sqrt(std::max(0.0, (ea + ec + std::sqrt((ea - ec) * (ea - ec) + 4 * eb * eb)) / 2));
    const double surface_area = 0.5 * norm(cross(q - p, r - p));
    sum += (ea + ec) / 2 * surface_area;
    weight += surface_area;
    out.linf = std::max(out.linf, big * scale);
  }
  out.l2 = weight > 0 ? std::sqrt(sum / weight) * scale : 0;
  return out;
}

std::array<float, 2> texcoord_of(const Vec2& square) {
  return {static_cast<float>((square[0] + 1) / 2), static_cast<float>((1 - square[1]) / 2)};
}

}  // namespace spheremap
