// Distance between two triangle surfaces: RMS and maximum (Hausdorff) in both directions,
// relative to the first surface's bounding-box diagonal, measured to the closest point of
// the other (an AABB tree over its triangles). The RMS is over one surface's vertices and
// triangle centroids; the maximum over every point of its triangles (refined_maximum.h:
// pieces cut where a bound says the maximum could be, to within 5% of it or 0.1% of the
// diagonal when more), so a long triangle over a gap is not judged by its corners.
#pragma once

#include <cmath>
#include <functional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {

struct SurfaceDistance {
  double rms_a_to_b = 0, max_a_to_b = 0;
  double rms_b_to_a = 0, max_b_to_a = 0;
  double hausdorff = 0;  // max of both directions
  // What the Hausdorff distance is at most: hausdorff plus the refinement's tolerance
  // (refined_maximum.h) when every piece settled (`hausdorff_settled`), else the largest
  // bound its budget left open (two nearly coinciding surfaces, a remesh of millions of
  // triangles: the figure above is then what was found, not certainly the maximum).
  double hausdorff_at_most = 0;
  bool hausdorff_settled = true;
  // Stopped once the Hausdorff distance found reached the caller's `give_up`: the figures
  // are what was measured by then (hausdorff at least give_up), not the surfaces' distance.
  bool gave_up = false;
  double rms = 0;       // over the samples of both directions
  double diagonal = 0;  // of a's bounding box: every figure above is divided by it
  size_t samples = 0;
};

// Which points the RMS is over (the maximum is over every point either way). Vertices
// alone: a third of the queries, where a surface and its neighbour lie near (an envelope
// fitted to its original) the refinement's bound by the nearest triangle settles each
// triangle from its corners. The RMS then weighs each vertex once instead of each vertex
// and centroid.
enum class DistanceSamples { kVerticesAndCentroids, kVertices };

SurfaceDistance surface_distance(std::span<const Vec3> a_positions,
                                 std::span<const Triangle> a_triangles,
                                 std::span<const Vec3> b_positions,
                                 std::span<const Triangle> b_triangles, int threads = 0,
                                 const std::function<bool()>* should_stop = nullptr,
                                 DistanceSamples which = DistanceSamples::kVerticesAndCentroids);

// surface_distance(a, b) twice from the same queries: to all of a's triangles, and to those
// whose `left_out` entry (one per triangle of a) is 0 (`kept`, as if they were a's only
// triangles, its figures relative to their own diagonal). Each RMS equals that of the
// separate call: the same samples and distances, summed in the same order; b's samples
// find the nearest kept triangle in the one tree over all (TriangleTree::closest with
// left_out). Each maximum is within the same tolerance of the true one, but may be larger
// than the separate call's (a piece cut for one figure measures both). E.g. a remesh
// against the input's own faces and against them with the fills.
struct SurfaceDistances {
  SurfaceDistance kept, all;
};
SurfaceDistances surface_distances(std::span<const Vec3> a_positions,
                                   std::span<const Triangle> a_triangles,
                                   std::span<const char> left_out,
                                   std::span<const Vec3> b_positions,
                                   std::span<const Triangle> b_triangles, int threads = 0,
                                   const std::function<bool()>* should_stop = nullptr);

// The distance of each of `points` to the closest point of a's triangles (one query each,
// the same tree and frame as surface_distance), relative to a's bounding-box diagonal:
// e.g. a heat map of how far an envelope's vertices lie from the original. All 0 when a
// has no extent. `should_stop` (may be null) is asked every 4096 points; true throws
// InputError("stopped").
struct PointDistances {
  std::vector<double> relative;  // one per point
  double diagonal = 0;           // of a's bounding box, in a's units
};
PointDistances point_distances(std::span<const Vec3> a_positions,
                               std::span<const Triangle> a_triangles, std::span<const Vec3> points,
                               int threads = 0, const std::function<bool()>* should_stop = nullptr);

// One surface a, measured against several: its unit frame and closest-point tree built
// once. The functions above are each one call of it; a remesh that tries several frames
// measures every one against the same surface (the tree over a 100K-triangle surface is
// a tenth of a remesh's distance). The answers are those of the functions above, bit for
// bit. Holds a copy of a's positions and its tree: O(a) memory.
class SurfaceMeasure {
 public:
  SurfaceMeasure(std::span<const Vec3> a_positions, std::span<const Triangle> a_triangles);
  // `give_up` (relative, as hausdorff): a caller that keeps only a surface nearer than some
  // other stops the measure once the Hausdorff distance found reaches it (`gave_up`; a
  // surface nearer than it is measured exactly as without it).
  SurfaceDistance distance_to(std::span<const Vec3> b_positions,
                              std::span<const Triangle> b_triangles, int threads = 0,
                              const std::function<bool()>* should_stop = nullptr,
                              double give_up = INFINITY,
                              DistanceSamples which = DistanceSamples::kVerticesAndCentroids) const;
  // `left_out`: one entry per triangle of a (surface_distances). `give_up`: of the kept
  // figure.
  SurfaceDistances distances_to(std::span<const char> left_out, std::span<const Vec3> b_positions,
                                std::span<const Triangle> b_triangles, int threads = 0,
                                const std::function<bool()>* should_stop = nullptr,
                                double give_up = INFINITY) const;
  PointDistances point_distances(std::span<const Vec3> points, int threads = 0,
                                 const std::function<bool()>* should_stop = nullptr) const;
  // The largest of point_distances(points).relative (0 without points), bit for bit,
  // without measuring a point exactly once some triangle is found as near as the largest
  // so far (a remesh's screen needs only its largest error).
  double largest_point_distance(std::span<const Vec3> points, int threads = 0,
                                const std::function<bool()>* should_stop = nullptr) const;

 private:
  std::vector<Triangle> triangles_;
  UnitFrame frame_;
  std::vector<Vec3> unit_;  // a's positions in frame_
  double diagonal_ = 0;     // of a's triangles' corners, in frame_
  TriangleTree tree_;       // over all of a's triangles, in frame_
};

}  // namespace spheremap
