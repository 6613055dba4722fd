// Texture coordinates for the original surface from the octahedral square (ALGORITHM §E):
// every vertex gets (u, v) = the unfolding of its sphere point. The unfolding is cut along
// the lower half of the planes x = 0 and y = 0, so triangles reaching across a cut are
// clipped there (on the chord triangle, which central projection keeps on the sphere);
// the points on a cut get one vertex per side, and no triangle's UVs span the cut.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/outputs/octahedral.h"

namespace spheremap {

struct UvMesh {
  std::vector<Vec3> positions;  // on the original surface
  std::vector<Vec2> square;     // (u, v) in [-1, 1]^2 per vertex
  std::vector<Triangle> triangles;
  size_t split_triangles = 0;  // input triangles clipped at the octant planes
  size_t seam_vertices = 0;    // vertices made by clipping, or copied for a cut's other side
  // Triangles whose (u, v) area is negative. Within an octant the unfolding keeps the
  // orientation, so a flip here is a fold of the map itself (a sliver whose sign double
  // precision got wrong), never the cut.
  size_t flipped = 0;
  size_t degenerate = 0;  // (u, v) corners collinear within rounding
};

// `triangles`: positively oriented on the sphere (a bijective map's oriented triangles).
UvMesh octahedral_texcoords(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                            std::span<const Triangle> triangles);

// Texture stretch of a parametrization (Sander et al. 2001): for the map from (u, v) to
// the surface, L2 = area-weighted RMS of sqrt((G^2 + g^2) / 2) and Linf = max G over the
// triangles (G >= g its singular values), with the (u, v) domain scaled to the surface's
// area, so 1 is perfect. Triangles of zero (u, v) area are skipped.
struct UvStretch {
  double l2 = 0, linf = 0;
};
UvStretch uv_stretch(std::span<const Vec3> surface, std::span<const Vec2> square,
                     std::span<const Triangle> triangles);

// glTF TEXCOORD_0 of a square point: [0, 1]^2 with v downwards (row 0 of an image is the
// square's top, v = 1).
std::array<float, 2> texcoord_of(const Vec2& square);

}  // namespace spheremap
