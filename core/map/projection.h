// The paper's initial map (ALGORITHM §A2): smooth the 3D mesh with A a few times, then
// project every vertex radially onto the unit sphere about a distance-weighted centroid.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/sparse_matrix.h"

namespace spheremap {

// C = sum_k w_k V_k, w_k = |V_k - G| / sum_j |V_j - G|, G the mean of the smoothed
// vertices. A vertex at C takes the mean direction of its A-neighbours.
std::vector<Vec3> project_to_sphere(std::span<const Vec3> positions, const SparseMatrix& A,
                                    int presmooth_steps, int threads);

}  // namespace spheremap
