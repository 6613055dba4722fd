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

// |spherical_area| for use as a weight: the same value, but small triangles (the vast
// majority) take atan(x) ~ x - x^3/3 + x^5/5 (relative error below 2e-8 for x < 0.1)
// instead of a full atan2, the largest cost of a smoothing iteration.
inline double unsigned_area_weight(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double num = std::abs(triple_product(a, b, c));
  const double den = 1.0 + dot(a, b) + dot(b, c) + dot(c, a);
  if (den > 0 && num < 0.1 * den) {
    const double x = num / den, x2 = x * x;
    return 2.0 * x * (1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0)));
  }
  return std::abs(2.0 * std::atan2(num, den));
}

}  // namespace spheremap
