// Octahedral remeshing (Praun & Hoppe 2003; ALGORITHM §E): a regular grid on the
// octahedral square, each sample located in the spherical map and the ORIGINAL surface
// interpolated there. The grid's border is stitched as the unfolding identifies it, so
// the remesh is a closed genus-0 surface; the grid coordinates are its texture
// coordinates and the sampled positions its geometry image.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/sphere_locator.h"

namespace spheremap {

struct OctahedralRemesh {
  int resolution = 0;  // N: quads per side, (N + 1)^2 samples
  // Per sample, row-major (index j * (N + 1) + i for u = -1 + 2i/N, v = -1 + 2j/N):
  std::vector<Vec3> positions;   // the original surface at the sample
  std::vector<Vec2> square;      // (u, v) in [-1, 1]^2
  std::vector<uint32_t> vertex;  // the stitched vertex: samples the border identifies share one
  size_t vertex_count = 0;       // distinct stitched vertices
  // Over samples, outward (counter-clockwise in (u, v)), two per quad: a quad off the
  // square's border is split along the diagonal nearer the surface at its centre, a border
  // quad along the octahedron's edge direction in its quadrant (remesh.cpp, quad_splits).
  std::vector<Triangle> triangles;
  size_t unlocated = 0;  // samples no map triangle held (0 for a bijective map): put on the nearest
  OctahedralFrame frame;  // sample s is the surface at the map's sphere point frame(square[s])
};

// `surface` and `sphere`: positions of the same vertices on the original surface and on
// the unit sphere; `triangles`: positively oriented on the sphere (a bijective map's
// oriented triangles). `resolution`: N >= 2, even (so the octahedron's edges are grid
// lines and diagonals). `threads`: 0 = all cores. `should_stop` (may be null), asked every
// few thousand samples from any thread: true throws InputError("stopped") (a 4096² grid
// locates 16M samples: seconds, which a time limit or a cancel must not wait for).
// `frame`: how the square lies on the sphere (octahedral_frame_choice.h picks one).
// `locator` (may be null: one is built): a SphereLocator of `sphere` and `triangles`, so
// remeshes over several frames share it (its grid takes longer than the sampling: scorpion
// 1.1 s, against 0.1 s to locate 16K samples).
OctahedralRemesh octahedral_remesh(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                                   std::span<const Triangle> triangles, int resolution,
                                   int threads = 0,
                                   const std::function<bool()>* should_stop = nullptr,
                                   const OctahedralFrame& frame = {},
                                   const SphereLocator* locator = nullptr);

// The remesh as a polygon mesh over its stitched vertices (for the topology checks).
PolygonMesh stitched_mesh(const OctahedralRemesh& remesh);

}  // namespace spheremap
