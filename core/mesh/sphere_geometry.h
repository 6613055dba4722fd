// Geometry on the unit sphere shared by every stage: guarded normalization, the
// triangle validity test (ALGORITHM §B1) and the spherical triangle area.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "core/mesh/vec3.h"

namespace spheremap {

// v / |v|, or `fallback` when v is (numerically) zero or not finite: rings summing to
// zero occur at coarse levels (a ring holding all four tetrahedron vertices).
inline Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  const double n2 = squared_norm(v);
  if (!(n2 > 1e-200) || !std::isfinite(n2)) return fallback;
  return v * (1.0 / std::sqrt(n2));
}

// An orthonormal basis (t1, t2) of the tangent plane at the unit vector p, with
// t1 x t2 = p: the frame every optimizer step at p is taken in.
inline std::array<Vec3, 2> tangent_frame(const Vec3& p) {
  const Vec3 axis = std::abs(p.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 t1 = normalized_or(cross(p, axis), Vec3{0, 0, 1});
  return {t1, cross(p, t1)};
}

inline double triple_product(const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(a, cross(b, c));
}

// Whether a . (b x c) > bound, in wider precision than double: x87 long double (64-bit
// mantissa, hardware) first, and where even that is within its rounding of the bound,
// __float128 (113 bits, software; each product of two doubles is exact there).
template <typename Wide>
Wide wide_triple_product(const Vec3& a, const Vec3& b, const Vec3& c) {
  auto w = [](double v) { return static_cast<Wide>(v); };
  return w(a.x) * (w(b.y) * w(c.z) - w(b.z) * w(c.y)) +
         w(a.y) * (w(b.z) * w(c.x) - w(b.x) * w(c.z)) +
         w(a.z) * (w(b.x) * w(c.y) - w(b.y) * w(c.x));
}

inline bool triple_product_exceeds(const Vec3& a, const Vec3& b, const Vec3& c, double bound) {
  const long double t = wide_triple_product<long double>(a, b, c) - bound;
  if (std::abs(t) > 1e-18L) return t > 0;
#if defined(__SIZEOF_FLOAT128__)
  return wide_triple_product<__float128>(a, b, c) > static_cast<__float128>(bound);
#else
  return t > 0;
#endif
}

// Valid = positively oriented by a margin relative to the longest edge, so triangles on
// a great circle do not pass; NaN is invalid. For unit vectors a double triple product
// is off by up to ~1e-15, so a small positive one is computed again in wide precision
// (measured: a beast sliver at +9e-18 in double is -1.4e-17 exactly, a fold the map
// would hide). Small negative ones stay invalid without the check: conservative (a
// triangle counts as valid only when its orientation is certain), and re-deciding them
// too cost scorpion's map 3-4x (thousands of slivers below 1e-18 each iteration).
inline bool is_valid_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest = std::max({squared_norm(b - a), squared_norm(c - a), squared_norm(c - b)});
  const double margin = 1e-10 * longest;
  const double t = triple_product(a, b, c);
  if (!(t > margin)) return false;  // conservative: only what double calls valid is re-checked
  if (t > margin + 1e-14) return true;
  return triple_product_exceeds(a, b, c, margin);
}

// The point as a glTF file stores it: each coordinate rounded to float32. A map that is
// valid in double can fold once its thinnest triangles are rounded.
inline Vec3 rounded_to_float32(const Vec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}
inline std::vector<Vec3> rounded_to_float32(std::span<const Vec3> points) {
  std::vector<Vec3> out(points.size());
  for (size_t v = 0; v < points.size(); ++v) out[v] = rounded_to_float32(points[v]);
  return out;
}

// Signed area of the spherical triangle (a, b, c) on the unit sphere (Van Oosterom-Strackee).
inline double spherical_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 2.0 * std::atan2(triple_product(a, b, c), 1.0 + dot(a, b) + dot(b, c) + dot(c, a));
}

// The same signed area for corners off the unit sphere (float32-rounded positions): the
// area of the triangle of their directions (Van Oosterom-Strackee for any lengths). The
// unit-length formula above is off by (|a| - 1) / (1 + a.b + b.c + c.a), which a triangle
// with nearly antipodal corners (a coarse CAD part's map) blows up to 1e-4 of 4 pi.
inline double spherical_area_of_directions(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = norm(a), lb = norm(b), lc = norm(c);
  return 2.0 * std::atan2(triple_product(a, b, c),
                          la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb);
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
