#include "core/mesh/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/parallel_stop.h"
#include "core/mesh/spatial_order.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {
namespace {

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

// The squared distance of each sample to the tree: one closest-point query each.
std::vector<double> squared_distances(std::span<const Vec3> samples, const TriangleTree& tree,
                                      int threads, const std::function<bool()>* should_stop) {
  std::vector<double> d2(samples.size());
  ParallelStop stop(should_stop, 4096);  // a few milliseconds of queries
  // Queried in Morton order (written back in sample order, so the sums are unchanged):
  // neighbouring queries walk the same nodes, 20% faster than the samples' own order.
  const std::vector<uint32_t> order = morton_order(samples);
  parallel_for(samples.size(), resolve_threads(threads), [&](size_t i) {
    if (!stop.skip(i)) d2[order[i]] = tree.squared_distance(samples[order[i]]);
  });
  stop.throw_if_stopped();
  return d2;
}

// {sum of squared distances, max distance} of the samples to the tree.
std::pair<double, double> one_way(const std::vector<Vec3>& samples, const TriangleTree& tree,
                                  int threads, const std::function<bool()>* should_stop) {
  const std::vector<double> d2 = squared_distances(samples, tree, threads, should_stop);
  double sum = 0, max = 0;
  for (double x : d2) sum += x, max = std::max(max, x);
  return {sum, std::sqrt(max)};
}

// `positions` moved into `frame`.
std::vector<Vec3> in_frame(const UnitFrame& frame, std::span<const Vec3> positions) {
  std::vector<Vec3> out(positions.size());
  for (size_t k = 0; k < out.size(); ++k) out[k] = frame.apply(positions[k]);
  return out;
}

// The diagonal of the box of the triangles' corners (0 without a triangle).
double corner_diagonal(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  AxisBox box;
  for (const Triangle& t : triangles)
    for (uint32_t v : t) box.add(positions[v]);
  return triangles.empty() ? 0 : norm(box.hi - box.lo);
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
  const std::vector<Vec3> a_unit = in_frame(frame, a_positions);
  const std::vector<Vec3> b_unit = in_frame(frame, b_positions);
  const double d = corner_diagonal(a_unit, a_triangles);
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

PointDistances point_distances(std::span<const Vec3> a_positions,
                               std::span<const Triangle> a_triangles, std::span<const Vec3> points,
                               int threads, const std::function<bool()>* should_stop) {
  PointDistances out;
  // In a's unit frame, as surface_distance measures.
  const UnitFrame frame = unit_frame(a_positions);
  const std::vector<Vec3> a_unit = in_frame(frame, a_positions);
  const std::vector<Vec3> p_unit = in_frame(frame, points);
  const double d = corner_diagonal(a_unit, a_triangles);
  out.diagonal = frame.length_in_input_units(d);
  out.relative.assign(points.size(), 0.0);
  if (!(d > 0)) return out;
  StopCheck(should_stop).check();  // before the tree: a million triangles take a while
  const std::vector<double> d2 =
      squared_distances(p_unit, TriangleTree(a_unit, a_triangles), threads, should_stop);
  for (size_t k = 0; k < d2.size(); ++k) out.relative[k] = std::sqrt(d2[k]) / d;
  return out;
}

}  // namespace spheremap
