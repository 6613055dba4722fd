// Barycentric weights of a point's projection onto a triangle's plane, clamped into the
// triangle: what interpolates a triangle's vertex attributes at a closest point.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/mesh/vec3.h"

namespace spheremap {

// The weights of p's projection onto the plane of abc in its corners (p on abc: its
// barycentric coordinates); a degenerate triangle answers its first corner.
inline std::array<double, 3> barycentric(const Vec3& p, const Vec3& a, const Vec3& b,
                                         const Vec3& c) {
  const Vec3 e0 = b - a, e1 = c - a, e2 = p - a;
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
  const double d20 = dot(e2, e0), d21 = dot(e2, e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 1e-30 * (d00 * d11 + 1e-300))) return {1, 0, 0};
  const double v = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
  const double w = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - v);
  return {1 - v - w, v, w};
}

}  // namespace spheremap
