// Turning a map's sphere to face the way its surface does, for the morph. The map starts
// from a tetrahedron, so its sphere is rotated arbitrarily against the mesh: a morph to it
// as it is swings every vertex across the model and collapses it halfway (spot.glb: the
// mean cosine between a vertex's direction from the centroid and its sphere point was
// -0.10). A rotation keeps the map what it is (bijective, same distortion), so the morph
// uses the best-fitting one. The sphere output itself stays as certified.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/vec3.h"

namespace spheremap {

struct SphereAlignment {
  double rotation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // row-major, det = +1
  std::vector<Vec3> sphere;  // rotation applied to every sphere point
  // Mean over vertices of cos(angle between position - centroid and sphere point), before
  // and after: 1 when every vertex points the way its sphere point does.
  double mean_cosine_before = 0, mean_cosine_after = 0;
};

// The proper rotation R maximising sum over v of <R sphere[v], positions[v] - centroid>
// (Kabsch, by the SVD of a 3x3 matrix). Preconditions: positions.size() == sphere.size();
// sphere points are unit vectors.
SphereAlignment align_sphere_to_surface(std::span<const Vec3> positions,
                                        std::span<const Vec3> sphere, const Vec3& centroid);

}  // namespace spheremap
