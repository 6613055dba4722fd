// Geometry on the unit sphere shared by every stage: guarded normalization, the
// triangle validity test (ALGORITHM §B1) and the spherical triangle area.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"

namespace spheremap {

// v / |v|, or `fallback` when v is (numerically) zero or not finite: rings summing to
// zero occur at coarse levels (a ring holding all four tetrahedron vertices).
inline Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  const double n2 = squared_norm(v);
  if (!(n2 > 1e-200) || !std::isfinite(n2)) return fallback;
  return v * (1.0 / std::sqrt(n2));
}

inline double triple_product(const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(a, cross(b, c));
}

// Valid = positively oriented by a margin relative to the longest edge, so triangles on
// a great circle do not pass; NaN is invalid.
inline bool is_valid_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest = std::max({squared_norm(b - a), squared_norm(c - a), squared_norm(c - b)});
  return triple_product(a, b, c) > 1e-10 * longest;
}

// Signed area of the spherical triangle (a, b, c) on the unit sphere (Van Oosterom-Strackee).
inline double spherical_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 2.0 * std::atan2(triple_product(a, b, c), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

}  // namespace spheremap
