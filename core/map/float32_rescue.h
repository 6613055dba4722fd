// The last step of a map certified in double: triangles that fold or collapse once their
// corners are rounded to float32 (as a glTF file stores them) get room.
//
// Why a step of its own: polish_map enlarges what the stretch energy sees, but a face of
// next to no area in 3D (a CAD sliver, a fill's thin corner) weighs nothing in that
// energy, so its spherical triangle may shrink to 1e-13 of the sphere and stay there; the
// float32 rounding (spacing 6e-8 on the unit sphere) then folds it. Manifold's test model
// Generic_Twin_7081 lost its 19,376-face body to one such triangle after four polish rounds.
#pragma once

#include <cstddef>
#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

// Each corner of a triangle that fails in float32 (invalid, or valid with a spherical area
// below kDegenerateArea, as check_map counts them on the rounded map) is moved to the
// Chebyshev centre of its star's kernel (kernel_center.h: the point farthest from every
// ring edge), kept only when its star stays valid in double and the smallest float32
// area of its star grows. Rounds until nothing fails or nothing moves, at most
// `max_rounds`.
// Inputs: `sphere`, unit vectors (a map of the closed manifold `triangles`, oriented so
// that a valid map has positive determinants). Vertices on a boundary or a non-manifold
// star, and stars over 48 corners, are left.
// Output: `sphere` changed in place; every moved vertex's star is valid in double, so a
// map valid in double stays so. Returns the vertices moved (0: the map is unchanged, as
// always when nothing fails in float32).
size_t rescue_float32(std::span<Vec3> sphere, std::span<const Triangle> triangles,
                      int max_rounds = 8);

}  // namespace spheremap
