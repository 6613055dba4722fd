#include "core/mesh/surface_distance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/parallel_stop.h"
#include "core/mesh/refined_maximum.h"
#include "core/mesh/spatial_order.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/submesh.h"
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

// Per position, the index of its sample in samples_of(positions, triangles) (unused
// positions: none, never read).
std::vector<uint32_t> vertex_samples(size_t vertex_count, std::span<const Triangle> triangles) {
  std::vector<uint32_t> index(vertex_count, UINT32_MAX);
  for (const Triangle& t : triangles)
    for (uint32_t v : t) index[v] = 0;
  auto next = static_cast<uint32_t>(triangles.size());
  for (uint32_t& k : index)
    if (k == 0) k = next++;
  return index;
}

// The maxima are found to within this share of themselves, or of the diagonal when more
// (refined_maximum.h): a remesh judged against 2% is judged on 2% +- 0.1%.
constexpr double kRelativeTolerance = 0.05, kDiagonalTolerance = 1e-3;

// Each sample's squared distance to the other surface, and its nearest triangle there.
struct SampleDistances {
  std::vector<double> d2;
  std::vector<uint32_t> nearest;
  explicit SampleDistances(size_t n) : d2(n), nearest(n, kNoNearest) {}
};

// The distance from a point to triangle t of (positions, triangles).
struct TriangleDistance {
  std::span<const Vec3> positions;
  std::span<const Triangle> triangles;
  double operator()(const Vec3& p, uint32_t t) const {
    const Triangle& tri = triangles[t];
    return norm(p -
                closest_on_triangle(p, positions[tri[0]], positions[tri[1]], positions[tri[2]]));
  }
};

// The largest distance over every point of `triangles`, not only at their samples:
// refined_maximum with the samples' measures (one or two figures: samples[k] for figure k,
// the second may be the first) and their maxima `reached`, relative tolerances to the
// figures' diagonals `diagonal`; the other surface (other_positions, other_triangles) for
// refined_maximum's budget and its bound by the nearest triangle; `give_up` as its.
RefinedMaximum maximum_over_triangles(
    std::span<const Vec3> positions, std::span<const Triangle> triangles,
    std::array<const SampleDistances*, 2> samples, DistancePair reached, DistancePair diagonal,
    const std::function<bool(size_t, int)>& counts,
    const std::function<PointMeasure(const Vec3&)>& measure, std::span<const Vec3> other_positions,
    std::span<const Triangle> other_triangles, int threads,
    const std::function<bool()>* should_stop, DistancePair give_up) {
  const std::vector<uint32_t> sample = vertex_samples(positions.size(), triangles);
  auto measure_at = [&](size_t k) {
    return PointMeasure{{std::sqrt(samples[0]->d2[k]), std::sqrt(samples[1]->d2[k])},
                        {samples[0]->nearest[k], samples[1]->nearest[k]}};
  };
  std::vector<PointMeasure> at_vertex(positions.size()), at_centroid(triangles.size());
  for (size_t v = 0; v < positions.size(); ++v)
    if (sample[v] != UINT32_MAX) at_vertex[v] = measure_at(sample[v]);
  for (size_t t = 0; t < triangles.size(); ++t) at_centroid[t] = measure_at(t);
  DistancePair tolerance;
  for (int k = 0; k < 2; ++k)
    tolerance[k] = std::max(kRelativeTolerance * reached[k], kDiagonalTolerance * diagonal[k]);
  const std::function<double(const Vec3&, uint32_t)> to_triangle =
      TriangleDistance{other_positions, other_triangles};
  return refined_maximum(positions, triangles, at_vertex, at_centroid, reached, tolerance, counts,
                         measure, other_triangles.size(), threads, should_stop, &to_triangle,
                         give_up);
}

// query(k) for each sample k, in parallel. Queried in Morton order (each query writes its
// own sample's entry, so the sums are unchanged): neighbouring queries walk the same nodes,
// 20% faster than the samples' own order.
template <class Query>
void query_samples(std::span<const Vec3> samples, int threads,
                   const std::function<bool()>* should_stop, Query query) {
  ParallelStop stop(should_stop, 4096);  // a few milliseconds of queries
  const std::vector<uint32_t> order = morton_order(samples);
  parallel_for(samples.size(), resolve_threads(threads), [&](size_t i) {
    if (!stop.skip(i)) query(order[i]);
  });
  stop.throw_if_stopped();
}

// Per sample of samples_of(positions, triangles) (`vertex_count` positions): 1 when it is a
// sample of the kept triangles alone too (a kept triangle's centroid, a vertex that a kept
// triangle uses). Those are a subsequence of the former: the same points in the same order.
std::vector<char> kept_samples(size_t vertex_count, std::span<const Triangle> triangles,
                               std::span<const char> left_out) {
  std::vector<char> kept(triangles.size(), 0), used(vertex_count, 0), kept_vertex(vertex_count, 0);
  for (size_t k = 0; k < triangles.size(); ++k)
    for (uint32_t v : triangles[k]) {
      used[v] = 1;
      if (!left_out[k]) kept_vertex[v] = 1, kept[k] = 1;
    }
  for (size_t v = 0; v < vertex_count; ++v)
    if (used[v]) kept.push_back(kept_vertex[v]);
  return kept;
}

// The squared distance of each sample from `first` on to the tree and its nearest
// triangle: one closest-point query each. The samples before `first` are not measured:
// infinitely far, nearest unknown (a bound taken from them bounds nothing).
SampleDistances sample_distances(std::span<const Vec3> samples, const TriangleTree& tree,
                                 int threads, const std::function<bool()>* should_stop,
                                 size_t first = 0) {
  SampleDistances out(samples.size());
  std::fill(out.d2.begin(), out.d2.begin() + first, INFINITY);
  query_samples(samples.subspan(first), threads, should_stop, [&](size_t k) {
    const TriangleTree::Closest nearest = tree.closest(samples[first + k]);
    out.d2[first + k] = nearest.squared_distance, out.nearest[first + k] = nearest.triangle;
  });
  return out;
}

// One direction's figures: the sum of its samples' squared distances, the largest distance
// over every point and what it is at most (refined_maximum.h).
struct OneWay {
  double sum = 0, max = 0, at_most = 0;
  bool settled = true;
  bool gave_up = false;  // stopped once max reached a give-up distance: the rest not measured
  // The maximum of figure k of `refined`.
  void take(const RefinedMaximum& refined, int k) {
    max = refined.reached[k], at_most = refined.at_most[k], settled = refined.settled[k];
  }
  // Whether max has reached `give_up`; then marked so.
  bool give_up_at(double give_up) {
    if (max >= give_up) gave_up = true, settled = false, at_most = INFINITY;
    return gave_up;
  }
};

// The sum and the largest of the samples from `first` on whose `counted` entry is set (all
// when it is empty), in sample order.
OneWay sum_and_max(const std::vector<double>& d2, std::span<const char> counted = {},
                   size_t first = 0) {
  double sum = 0, max = 0;
  for (size_t k = first; k < d2.size(); ++k)
    if (counted.empty() || counted[k]) sum += d2[k], max = std::max(max, d2[k]);
  return {sum, std::sqrt(max), std::sqrt(max)};
}

// The samples of `triangles` to the tree (of tree_positions and tree_triangles), the
// maximum over every point of them; tolerances relative to `diagonal`. Stops once the
// maximum reaches `give_up` (gave_up). Samples before `first` (the centroids, under
// DistanceSamples::kVertices) are neither measured nor summed.
OneWay one_way(std::span<const Vec3> positions, std::span<const Triangle> triangles,
               const std::vector<Vec3>& samples, size_t first, const TriangleTree& tree,
               std::span<const Vec3> tree_positions, std::span<const Triangle> tree_triangles,
               double diagonal, int threads, const std::function<bool()>* should_stop,
               double give_up) {
  const SampleDistances measured = sample_distances(samples, tree, threads, should_stop, first);
  OneWay out = sum_and_max(measured.d2, {}, first);
  if (out.give_up_at(give_up)) return out;
  const RefinedMaximum refined = maximum_over_triangles(
      positions, triangles, {&measured, &measured}, {out.max, out.max}, {diagonal, diagonal},
      [](size_t, int figure) { return figure == 0; },
      [&](const Vec3& p) {
        const TriangleTree::Closest nearest = tree.closest(p);
        return PointMeasure{{std::sqrt(nearest.squared_distance), 0},
                            {nearest.triangle, kNoNearest}};
      },
      tree_positions, tree_triangles, threads, should_stop, {give_up, INFINITY});
  out.take(refined, 0);
  out.give_up_at(give_up);
  return out;
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

// The figures of `out` from each direction's and its sample count, relative to a's
// diagonal `d`.
void finish(SurfaceDistance& out, const OneWay& a_to_b, size_t a_samples, const OneWay& b_to_a,
            size_t b_samples, double d) {
  out.rms_a_to_b = std::sqrt(a_to_b.sum / a_samples) / d;
  out.max_a_to_b = a_to_b.max / d;
  out.rms_b_to_a = std::sqrt(b_to_a.sum / b_samples) / d;
  out.max_b_to_a = b_to_a.max / d;
  out.hausdorff = std::max(out.max_a_to_b, out.max_b_to_a);
  out.hausdorff_at_most = std::max(a_to_b.at_most, b_to_a.at_most) / d;
  out.hausdorff_settled = a_to_b.settled && b_to_a.settled;
  out.gave_up = a_to_b.gave_up || b_to_a.gave_up;
  out.samples = a_samples + b_samples;
  out.rms = std::sqrt((a_to_b.sum + b_to_a.sum) / out.samples) / d;
}

}  // namespace

SurfaceMeasure::SurfaceMeasure(std::span<const Vec3> a_positions,
                               std::span<const Triangle> a_triangles)
    : triangles_(a_triangles.begin(), a_triangles.end()),
      frame_(unit_frame(a_positions)),
      unit_(in_frame(frame_, a_positions)),
      diagonal_(corner_diagonal(unit_, triangles_)),
      tree_(unit_, triangles_) {}

SurfaceDistance SurfaceMeasure::distance_to(std::span<const Vec3> b_positions,
                                            std::span<const Triangle> b_triangles, int threads,
                                            const std::function<bool()>* should_stop,
                                            double give_up, DistanceSamples which) const {
  SurfaceDistance out;
  // Both surfaces in a's unit frame: the figures are relative to a's diagonal, so a
  // similarity does not change them, and a mesh at 1e-300 units no longer underflows to
  // distance 0 (nor one at 1e200 overflows).
  const std::vector<Vec3> b_unit = in_frame(frame_, b_positions);
  const double d = diagonal_;
  out.diagonal = frame_.length_in_input_units(d);
  if (!(d > 0) || b_triangles.empty()) return out;
  const std::vector<Vec3> a_samples = samples_of(unit_, triangles_);
  const std::vector<Vec3> b_samples = samples_of(b_unit, b_triangles);
  // Asked before the tree too: building one over a million triangles takes a while.
  const StopCheck stop(should_stop);
  stop.check();
  const double give_up_at = give_up * d;
  // samples_of puts the centroids first.
  const bool centroids = which == DistanceSamples::kVerticesAndCentroids;
  const size_t a_first = centroids ? 0 : triangles_.size();
  const size_t b_first = centroids ? 0 : b_triangles.size();
  const auto a_to_b =
      one_way(unit_, triangles_, a_samples, a_first, TriangleTree(b_unit, b_triangles), b_unit,
              b_triangles, d, threads, should_stop, give_up_at);
  stop.check();
  const auto b_to_a = a_to_b.gave_up
                          ? OneWay{}
                          : one_way(b_unit, b_triangles, b_samples, b_first, tree_, unit_,
                                    triangles_, d, threads, should_stop, give_up_at);
  finish(out, a_to_b, a_samples.size() - a_first, b_to_a, b_samples.size() - b_first, d);
  return out;
}

SurfaceDistances SurfaceMeasure::distances_to(std::span<const char> left_out,
                                              std::span<const Vec3> b_positions,
                                              std::span<const Triangle> b_triangles, int threads,
                                              const std::function<bool()>* should_stop,
                                              double give_up) const {
  if (left_out.size() != triangles_.size())
    throw std::invalid_argument("surface_distances: one left_out entry per triangle of a");
  SurfaceDistances out;
  const std::vector<Vec3> b_unit = in_frame(frame_, b_positions);  // as distance_to
  const std::vector<Triangle> kept = kept_triangles(triangles_, left_out);
  const double d_all = diagonal_;
  const double d_kept = corner_diagonal(unit_, kept);
  out.all.diagonal = frame_.length_in_input_units(d_all);
  out.kept.diagonal = frame_.length_in_input_units(d_kept);
  if (!(d_all > 0) || b_triangles.empty()) return out;
  const std::vector<Vec3> a_samples = samples_of(unit_, triangles_);
  const std::vector<char> kept_sample = kept_samples(unit_.size(), triangles_, left_out);
  const size_t a_kept_samples = std::count(kept_sample.begin(), kept_sample.end(), 1);
  const std::vector<Vec3> b_samples = samples_of(b_unit, b_triangles);
  const StopCheck stop(should_stop);
  stop.check();
  const TriangleTree b_tree(b_unit, b_triangles);
  const SampleDistances a_d2 = sample_distances(a_samples, b_tree, threads, should_stop);
  stop.check();
  // Per b sample: its squared distance to all of a, and to the kept triangles alone (the
  // same answer when the nearest triangle is kept; else a second search, skipping the rest).
  SampleDistances b_all_d2(b_samples.size()), b_kept_d2(b_samples.size());
  const TriangleTree& a_tree = tree_;
  // A point's nearest triangle of all of a, and of its kept triangles.
  const auto nearest_pair = [&](const Vec3& p) {
    const TriangleTree::Closest nearest = a_tree.closest(p);
    return std::pair{nearest, left_out[nearest.triangle] ? a_tree.closest(p, left_out) : nearest};
  };
  query_samples(b_samples, threads, should_stop, [&](size_t k) {
    const auto [all, kept] = nearest_pair(b_samples[k]);
    b_all_d2.d2[k] = all.squared_distance, b_all_d2.nearest[k] = all.triangle;
    b_kept_d2.d2[k] = kept.squared_distance, b_kept_d2.nearest[k] = kept.triangle;
  });
  // The maxima over every point (refined_maximum.h): a's kept triangles count for both
  // figures, the others for `all` alone; b's for both, measured to all of a and to its kept
  // triangles.
  auto a_all = sum_and_max(a_d2.d2), a_kept = sum_and_max(a_d2.d2, kept_sample);
  auto b_all = sum_and_max(b_all_d2.d2), b_kept = sum_and_max(b_kept_d2.d2);
  // Once the kept figure reaches give_up, nothing more is measured (every figure gave up).
  const double give_up_at = give_up * d_kept;
  const auto finished = [&](bool gave_up) {
    if (gave_up)
      for (OneWay* one : {&a_all, &a_kept, &b_all, &b_kept}) one->give_up_at(-INFINITY);
    finish(out.all, a_all, a_samples.size(), b_all, b_samples.size(), d_all);
    if (d_kept > 0) finish(out.kept, a_kept, a_kept_samples, b_kept, b_samples.size(), d_kept);
    return out;
  };
  if (std::max(a_kept.max, b_kept.max) >= give_up_at) return finished(true);
  const RefinedMaximum a_max = maximum_over_triangles(
      unit_, triangles_, {&a_d2, &a_d2}, {a_all.max, a_kept.max}, {d_all, d_kept},
      [&](size_t t, int figure) { return figure == 0 || !left_out[t]; },
      [&](const Vec3& p) {
        const TriangleTree::Closest nearest = b_tree.closest(p);
        const double d = std::sqrt(nearest.squared_distance);
        return PointMeasure{{d, d}, {nearest.triangle, nearest.triangle}};
      },
      b_unit, b_triangles, threads, should_stop, {INFINITY, give_up_at});
  a_all.take(a_max, 0), a_kept.take(a_max, 1);
  if (a_kept.max >= give_up_at) return finished(true);
  const RefinedMaximum b_max = maximum_over_triangles(
      b_unit, b_triangles, {&b_all_d2, &b_kept_d2}, {b_all.max, b_kept.max}, {d_all, d_kept},
      [](size_t, int) { return true; },
      [&](const Vec3& p) {
        const auto [all, kept] = nearest_pair(p);
        return PointMeasure{{std::sqrt(all.squared_distance), std::sqrt(kept.squared_distance)},
                            {all.triangle, kept.triangle}};
      },
      unit_, triangles_, threads, should_stop, {INFINITY, give_up_at});
  b_all.take(b_max, 0), b_kept.take(b_max, 1);
  return finished(b_kept.max >= give_up_at);
}

PointDistances SurfaceMeasure::point_distances(std::span<const Vec3> points, int threads,
                                               const std::function<bool()>* should_stop) const {
  PointDistances out;
  const std::vector<Vec3> p_unit = in_frame(frame_, points);  // as distance_to measures
  const double d = diagonal_;
  out.diagonal = frame_.length_in_input_units(d);
  out.relative.assign(points.size(), 0.0);
  if (!(d > 0)) return out;
  const SampleDistances measured = sample_distances(p_unit, tree_, threads, should_stop);
  for (size_t k = 0; k < measured.d2.size(); ++k) out.relative[k] = std::sqrt(measured.d2[k]) / d;
  return out;
}

double SurfaceMeasure::largest_point_distance(std::span<const Vec3> points, int threads,
                                              const std::function<bool()>* should_stop) const {
  const std::vector<Vec3> p_unit = in_frame(frame_, points);  // as point_distances measures
  const double d = diagonal_;
  if (!(d > 0) || p_unit.empty()) return 0;
  // The largest squared distance so far, shared: a thread reading a stale (smaller) value
  // only measures more points exactly, so the result does not depend on the threads.
  std::atomic<double> largest{0};
  query_samples(p_unit, threads, should_stop, [&](size_t k) {
    double seen = largest.load(std::memory_order_relaxed);
    const double d2 = tree_.squared_distance_over(p_unit[k], seen);
    while (d2 > seen && !largest.compare_exchange_weak(seen, d2, std::memory_order_relaxed)) {
    }
  });
  return std::sqrt(largest.load()) / d;
}

// Each one measure; asked before its tree (a million triangles take a while).
SurfaceDistance surface_distance(std::span<const Vec3> a_positions,
                                 std::span<const Triangle> a_triangles,
                                 std::span<const Vec3> b_positions,
                                 std::span<const Triangle> b_triangles, int threads,
                                 const std::function<bool()>* should_stop, DistanceSamples which) {
  StopCheck(should_stop).check();
  return SurfaceMeasure(a_positions, a_triangles)
      .distance_to(b_positions, b_triangles, threads, should_stop, INFINITY, which);
}

SurfaceDistances surface_distances(std::span<const Vec3> a_positions,
                                   std::span<const Triangle> a_triangles,
                                   std::span<const char> left_out,
                                   std::span<const Vec3> b_positions,
                                   std::span<const Triangle> b_triangles, int threads,
                                   const std::function<bool()>* should_stop) {
  if (left_out.size() != a_triangles.size())
    throw std::invalid_argument("surface_distances: one left_out entry per triangle of a");
  StopCheck(should_stop).check();
  return SurfaceMeasure(a_positions, a_triangles)
      .distances_to(left_out, b_positions, b_triangles, threads, should_stop);
}

PointDistances point_distances(std::span<const Vec3> a_positions,
                               std::span<const Triangle> a_triangles, std::span<const Vec3> points,
                               int threads, const std::function<bool()>* should_stop) {
  StopCheck(should_stop).check();
  return SurfaceMeasure(a_positions, a_triangles).point_distances(points, threads, should_stop);
}

}  // namespace spheremap
