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
// The prediction: at a vertex v of the map, the surface area one sample stands for is
// proportional to (A_v / S_v) |R^T q_v|_1^3, with A_v the surface area of v's triangles, S_v
// their chord area on the sphere, q_v its sphere point and R the frame's rotation (the
// square's area per solid angle at direction d is sqrt(3) / |d|_1^3); its square root is the
// spacing of the samples there. The frame chosen is the one among fixed candidates (spread
// evenly over the rotations) whose largest predicted spacing is smallest. It is a
// prediction only (bridging needs a feature under the sparse spot), so the remesh keeps
// whichever of this frame and the unturned one measures nearer (map_outputs.cpp): on 15
// set-8 CAD parts whose remesh stood over 2% of the diagonal, the two together
// measured as well as the best of four random frames.
#pragma once

#include <span>

#include "core/mesh/mesh.h"
#include "core/outputs/octahedral.h"

namespace spheremap {

// The candidates besides the unturned frame.
inline constexpr int kFrameCandidates = 48;

struct FrameChoice {
  OctahedralFrame frame;  // the candidate of smallest largest predicted spacing
  // Largest predicted spacing (relative: sqrt of surface area share per steradian share)
  // of the chosen frame and of the unturned one.
  double predicted_spacing = 0, unturned_spacing = 0;
};

// `surface` and `sphere`: per vertex, its position and its unit sphere point; `triangles`
// of the map (bijective or not: only areas are read). Vertices no triangle uses, and
// triangles of zero chord area, are skipped. Deterministic and the same on every platform
// (the candidates are Halton points taken to rotations by Shoemake's formula).
FrameChoice choose_octahedral_frame(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                                    std::span<const Triangle> triangles);

// Candidate k (0-based, k < kFrameCandidates) of that list, for tests and benches.
OctahedralFrame frame_candidate(int k);

}  // namespace spheremap
