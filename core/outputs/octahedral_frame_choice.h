// Choosing the octahedral frame of a remesh (octahedral.h, OctahedralFrame): which way the
// remesh's square lies on the map's sphere.
//
// A remesh samples the surface at a regular grid of the square; the unfolding makes that
// grid 5.2 times denser (per unit of solid angle) at the octahedron's six vertices than at
// its eight face centres, and the map itself gives some parts of the surface much less of
// the sphere than others (a CAD part's small bosses and ribs: a hundred times less than
// its plates). Where both are sparse, remesh triangles bridge the surface's features, and
// that is where the remesh's Hausdorff distance comes from. Turning the square moves its
// dense spots onto the parts the map squeezed.
//
// Two predictions of a better frame, each over 48 fixed candidate rotations (Halton points
// through Shoemake's formula: the same on every platform):
// - from the map alone: at a vertex v, the surface area one sample stands for is
//   proportional to (A_v / S_v) |R^T q_v|_1^3, with A_v the surface area of v's triangles,
//   S_v their chord area on the sphere, q_v its sphere point and R the frame's rotation (the
//   square's area per solid angle at direction d is sqrt(3) / |d|_1^3); its square root is
//   the spacing of the samples there, and the candidate whose largest is least is chosen;
// - from a remesh's own errors (sampled_errors: at its triangles' centroids and at the
//   surface's vertices): each error scaled by how the spacing at its sphere point changes,
//   and the candidate whose largest predicted error is least is chosen.
// Neither can be trusted alone (bridging needs a feature under a sparse spot, and an error
// need not shrink with the spacing): on 15 set-8 CAD parts whose remesh stood over 2% of
// the diagonal, a rotation chosen by the first alone made some files worse (3.2% -> 5.2%),
// and each of the two was the better on about half of the files and of the corpus. So the
// remesh (map_outputs.cpp) samples the best few of both rankings, screens them by their
// sampled errors, measures the best few of those in full beside the unturned remesh, and
// keeps the nearest.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/outputs/octahedral.h"

namespace spheremap {

// The candidates besides the unturned frame.
inline constexpr int kFrameCandidates = 48;

// Turned frames are tried only when the unturned remesh stands farther than this from the
// surface (its Hausdorff distance over the diagonal): trying costs about a second full
// distance (horse at resolution 128: the remesh stage 0.32 -> 0.81 s, idle), and
// what it gains is a fraction of the distance (the corpus at 128, where turning helped:
// 0.03% to 0.56% of the diagonal, median 0.12%), which matters where the remesh is far.
inline constexpr double kFrameTrialDistance = 0.005;

// Where frames are tried (map_outputs.cpp) at a resolution up to kFrameSearchResolution:
// each ranking's best kFramesScreened sampled and screened by their sampled errors, and
// the best kFramesMeasured of those measured in full. Above it both shrink with the
// samples per grid (frames_tried), down to one each (from 512), so a large remesh samples
// no more grids than it did with one frame of each ranking.
inline constexpr size_t kFramesScreened = 12;
inline constexpr size_t kFramesMeasured = 3;
// 128: the screens and measures cost in proportion to the samples, and at 256 the full
// search took a CAD part's remesh stage from 3.8 s to 11.8 s (xy_joint_right_lower_MGN12,
// idle, one thread; 2.18% -> 1.74% off); at 128, 2.1 s -> 5.6 s (3.86% -> 2.87%).
inline constexpr int kFrameSearchResolution = 128;

// `most` (kFramesScreened or kFramesMeasured) at `resolution`: most x
// (kFrameSearchResolution / resolution)^2, at least 1 and at most `most`.
size_t frames_tried(size_t most, int resolution);

struct FrameChoice {
  OctahedralFrame frame;  // the candidate whose largest predicted figure is least
  // That largest figure (a sample spacing from the map's areas, or an error from a
  // remesh's errors), for the chosen frame and for the unturned one.
  double predicted_largest = 0, unturned_largest = 0;
  // Every candidate's index (frame_candidate), least largest figure first: `frame` is
  // ranked[0]'s.
  std::vector<int> ranked;
};

// `surface` and `sphere`: per vertex, its position and its unit sphere point; `triangles`
// of the map (bijective or not: only areas are read). Vertices no triangle uses, and
// triangles of zero chord area, are skipped. Deterministic and the same on every platform
// (the candidates are Halton points taken to rotations by Shoemake's formula).
FrameChoice choose_octahedral_frame(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                                    std::span<const Triangle> triangles);

// An error measured on a remesh, and the sphere point where it was measured.
struct SampledError {
  Vec3 direction;  // on the map's sphere
  double error = 0;
};
struct OctahedralRemesh;
class SurfaceMeasure;

// The errors of `remesh` (made over some frame): at each of its triangles' centroids, the
// distance to the surface (`measured_surface`: SurfaceMeasure(surface, the map's
// triangles), built once for every remesh measured), and at each surface vertex
// (`surface`) the distance to the remesh; relative to the measured surface's diagonal.
std::vector<SampledError> sampled_errors(const SurfaceMeasure& measured_surface,
                                         std::span<const Vec3> surface,
                                         std::span<const Vec3> sphere,
                                         const OctahedralRemesh& remesh, int threads,
                                         const std::function<bool()>* should_stop);

// The largest of sampled_errors(...)'s errors, bit for bit, without measuring exactly the
// points that cannot be it (SurfaceMeasure::largest_point_distance): a screen of a frame.
double largest_sampled_error(const SurfaceMeasure& measured_surface, std::span<const Vec3> surface,
                             const OctahedralRemesh& remesh, int threads,
                             const std::function<bool()>* should_stop);

// The candidate whose predicted largest error is least, each error scaled by the sample
// spacing there in the candidate's frame over that in `measured` (the frame the errors
// were measured in): (|R^T d|_1 / |M^T d|_1)^(3/2).
FrameChoice choose_octahedral_frame(std::span<const SampledError> errors,
                                    const OctahedralFrame& measured);

// Candidate k (0-based, k < kFrameCandidates) of that list, for tests and benches.
OctahedralFrame frame_candidate(int k);

}  // namespace spheremap
