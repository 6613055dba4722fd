// The octahedral unfolding of the unit sphere onto the square [-1,1]^2 (Praun & Hoppe
// 2003; ALGORITHM §E): the upper half (z >= 0) is (x, y) / (|x|+|y|+|z|), the lower half is
// folded into the corners. Continuous inside each quadrant (signs of x and y); the cuts
// are the lower half of the planes x = 0 and y = 0, which become the square's border,
// where (1, v) ~ (1, -v), (-1, v) ~ (-1, -v), (u, 1) ~ (-u, 1), (u, -1) ~ (-u, -1).
#pragma once

#include <array>

#include "core/mesh/vec3.h"

namespace spheremap {

using Vec2 = std::array<double, 2>;

// A unit (or any non-zero) vector to the square.
Vec2 octahedral_encode(const Vec3& direction);

// A point of the square to the unit sphere.
Vec3 octahedral_decode(const Vec2& square);

// How the square is laid over a map's sphere: the sphere point of square point s is
// rotation * octahedral_decode(s). The unfolding samples the sphere unevenly (per unit of
// solid angle, 3 sqrt(3) = 5.2 times as densely at the six axes as at the eight face
// centres), so turning it changes which parts of a surface a remesh resolves best; any
// rotation keeps a bijective map bijective.
struct OctahedralFrame {
  double rotation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // row-major, proper
  Vec3 to_sphere(const Vec3& d) const;                        // rotation * d
  Vec3 from_sphere(const Vec3& d) const;                      // rotation^T * d
  bool identity() const;
  bool operator==(const OctahedralFrame&) const = default;
};

// octahedral_decode turned by the frame: the map's sphere point of square point s.
Vec3 octahedral_decode(const Vec2& square, const OctahedralFrame& frame);

}  // namespace spheremap
