// The point of a spherical star polygon's kernel farthest from all its edges.
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "core/mesh/vec3.h"

namespace spheremap {

// ring: unit vectors r_0..r_m-1, an oriented cycle; the kernel is every p with
// p . (r_i x r_i+1) > 0 for all i (all star triangles (p, r_i, r_i+1) positive).
// Solved exactly in the gnomonic projection about `center` (lines stay lines there):
// the Chebyshev centre of the intersection of half-planes, a 3-variable linear program
// solved by enumerating constraint triples (rings are small; capped at
// kKernelCenterMaxCorners corners, O(m^4) beyond which it is not worth it).
// Returns nothing when the kernel is empty, or a ring point is not in the open
// hemisphere around `center`.
inline constexpr size_t kKernelCenterMaxCorners = 48;
std::optional<Vec3> kernel_center(std::span<const Vec3> ring, const Vec3& center);

}  // namespace spheremap
