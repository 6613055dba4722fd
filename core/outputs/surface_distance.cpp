#include "core/outputs/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/parallel_stop.h"
#include "core/mesh/stop_check.h"

namespace spheremap {
namespace {

// The closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate triangle
  return a + ab * (vb / denom) + ac * (vc / denom);
}

struct Box {
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::lowest()};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  double squared_distance(const Vec3& p) const {
    const double dx = std::max({lo.x - p.x, 0.0, p.x - hi.x});
    const double dy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
    const double dz = std::max({lo.z - p.z, 0.0, p.z - hi.z});
    return dx * dx + dy * dy + dz * dz;
  }
};

// An AABB tree over triangles for closest-point queries.
class TriangleTree {
 public:
  TriangleTree(std::span<const Vec3> positions, std::span<const Triangle> triangles)
      : positions_(positions), triangles_(triangles), order_(triangles.size()) {
    std::iota(order_.begin(), order_.end(), 0u);
    centroids_.resize(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
      centroids_[t] =
          (positions[triangles[t][0]] + positions[triangles[t][1]] + positions[triangles[t][2]]) *
          (1.0 / 3);
    if (triangles.empty()) return;
    nodes_.reserve(2 * triangles.size() / 4 + 2);
    nodes_.emplace_back();
    build(0, 0, triangles.size());
  }

  double squared_distance(const Vec3& p) const {
    double best = std::numeric_limits<double>::max();
    if (nodes_.empty()) return best;
    std::vector<uint32_t> stack = {0};
    while (!stack.empty()) {
      const Node& node = nodes_[stack.back()];
      stack.pop_back();
      if (node.box.squared_distance(p) >= best) continue;
      if (node.count) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
          const Triangle& t = triangles_[order_[k]];
          const Vec3 q =
              closest_on_triangle(p, positions_[t[0]], positions_[t[1]], positions_[t[2]]);
          best = std::min(best, squared_norm(q - p));
        }
        continue;
      }
      // Nearer child last, so it is searched first.
      const uint32_t l = node.first, r = node.first + 1;
      const bool left_nearer =
          nodes_[l].box.squared_distance(p) < nodes_[r].box.squared_distance(p);
      stack.push_back(left_nearer ? r : l);
      stack.push_back(left_nearer ? l : r);
    }
    return best;
  }

 private:
  struct Node {
    Box box;
    uint32_t first = 0;  // leaf: first triangle in order_; inner: left child (right = +1)
    uint32_t count = 0;  // leaf: triangles; 0 for an inner node
  };

  // Fills node `index` (already allocated) with triangles order_[begin, end).
  void build(uint32_t index, size_t begin, size_t end) {
    Box box, centres;
    for (size_t k = begin; k < end; ++k) {
      for (uint32_t v : triangles_[order_[k]]) box.add(positions_[v]);
      centres.add(centroids_[order_[k]]);
    }
    nodes_[index].box = box;
    if (end - begin <= 4) {
      nodes_[index].first = static_cast<uint32_t>(begin);
      nodes_[index].count = static_cast<uint32_t>(end - begin);
      return;
    }
    const Vec3 extent = centres.hi - centres.lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const size_t mid = (begin + end) / 2;
    std::nth_element(
        order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
        [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    const uint32_t left = static_cast<uint32_t>(nodes_.size());  // the right child is left + 1
    nodes_.resize(nodes_.size() + 2);
    nodes_[index].first = left;
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  std::span<const Vec3> positions_;
  std::span<const Triangle> triangles_;
  std::vector<uint32_t> order_;
  std::vector<Vec3> centroids_;
  std::vector<Node> nodes_;
};

// Samples of a surface: its vertices (used by a triangle) and its triangle centroids.
std::vector<Vec3> samples_of(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  std::vector<char> used(positions.size(), 0);
  std::vector<Vec3> out;
  for (const Triangle& t : triangles) {
    for (uint32_t v : t) used[v] = 1;
    out.push_back((positions[t[0]] + positions[t[1]] + positions[t[2]]) * (1.0 / 3));
  }
  for (size_t v = 0; v < positions.size(); ++v)
    if (used[v]) out.push_back(positions[v]);
  return out;
}

// {sum of squared distances, max distance} of the samples to the tree.
std::pair<double, double> one_way(const std::vector<Vec3>& samples, const TriangleTree& tree,
                                  int threads, const std::function<bool()>* should_stop) {
  std::vector<double> d2(samples.size());
  ParallelStop stop(should_stop, 4096);  // a few milliseconds of queries
  parallel_for(samples.size(), resolve_threads(threads), [&](size_t i) {
    if (!stop.skip(i)) d2[i] = tree.squared_distance(samples[i]);
  });
  stop.throw_if_stopped();
  double sum = 0, max = 0;
  for (double x : d2) sum += x, max = std::max(max, x);
  return {sum, std::sqrt(max)};
}

}  // namespace

SurfaceDistance surface_distance(std::span<const Vec3> a_positions,
                                 std::span<const Triangle> a_triangles,
                                 std::span<const Vec3> b_positions,
                                 std::span<const Triangle> b_triangles, int threads,
                                 const std::function<bool()>* should_stop) {
  SurfaceDistance out;
  // Both surfaces in a's unit frame: the figures are relative to a's diagonal, so a
  // similarity does not change them, and a mesh at 1e-300 units no longer underflows to
  // distance 0 (nor one at 1e200 overflows).
  const UnitFrame frame = unit_frame(a_positions);
  std::vector<Vec3> a_unit(a_positions.size()), b_unit(b_positions.size());
  for (size_t k = 0; k < a_unit.size(); ++k) a_unit[k] = frame.apply(a_positions[k]);
  for (size_t k = 0; k < b_unit.size(); ++k) b_unit[k] = frame.apply(b_positions[k]);
  Box box;
  for (const Triangle& t : a_triangles)
    for (uint32_t v : t) box.add(a_unit[v]);
  const double d = a_triangles.empty() ? 0 : norm(box.hi - box.lo);
  out.diagonal = frame.length_in_input_units(d);
  if (!(d > 0) || b_triangles.empty()) return out;
  const std::vector<Vec3> a_samples = samples_of(a_unit, a_triangles);
  const std::vector<Vec3> b_samples = samples_of(b_unit, b_triangles);
  // Asked before each tree too: building one over a million triangles takes a while.
  const StopCheck stop(should_stop);
  stop.check();
  const auto [a_sum, a_max] =
      one_way(a_samples, TriangleTree(b_unit, b_triangles), threads, should_stop);
  stop.check();
  const auto [b_sum, b_max] =
      one_way(b_samples, TriangleTree(a_unit, a_triangles), threads, should_stop);
  out.rms_a_to_b = std::sqrt(a_sum / a_samples.size()) / d;
  out.max_a_to_b = a_max / d;
  out.rms_b_to_a = std::sqrt(b_sum / b_samples.size()) / d;
  out.max_b_to_a = b_max / d;
  out.hausdorff = std::max(out.max_a_to_b, out.max_b_to_a);
  out.samples = a_samples.size() + b_samples.size();
  out.rms = std::sqrt((a_sum + b_sum) / out.samples) / d;
  return out;
}

}  // namespace spheremap
