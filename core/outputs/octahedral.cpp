#include "core/outputs/octahedral.h"

#include <cmath>

namespace spheremap {
namespace {

double sign_of(double v) {
  return v < 0 ? -1.0 : 1.0;
}  // 0 counts as positive

}  // namespace

Vec2 octahedral_encode(const Vec3& d) {
  const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
  const double x = d.x / l1, y = d.y / l1;
  if (d.z >= 0) return {x, y};
  return {(1 - std::abs(y)) * sign_of(x), (1 - std::abs(x)) * sign_of(y)};
}

Vec3 octahedral_decode(const Vec2& s) {
  double x = s[0], y = s[1];
  const double z = 1 - std::abs(x) - std::abs(y);
  if (z < 0) {
    const double folded_x = (1 - std::abs(y)) * sign_of(x);
    y = (1 - std::abs(x)) * sign_of(y);
    x = folded_x;
  }
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}

Vec3 OctahedralFrame::to_sphere(const Vec3& d) const {
  const auto& r = rotation;
  return {r[0][0] * d.x + r[0][1] * d.y + r[0][2] * d.z,
          r[1][0] * d.x + r[1][1] * d.y + r[1][2] * d.z,
          r[2][0] * d.x + r[2][1] * d.y + r[2][2] * d.z};
}

Vec3 OctahedralFrame::from_sphere(const Vec3& d) const {
  const auto& r = rotation;
  return {r[0][0] * d.x + r[1][0] * d.y + r[2][0] * d.z,
          r[0][1] * d.x + r[1][1] * d.y + r[2][1] * d.z,
          r[0][2] * d.x + r[1][2] * d.y + r[2][2] * d.z};
}

bool OctahedralFrame::identity() const {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (rotation[i][j] != (i == j ? 1.0 : 0.0)) return false;
  return true;
}

Vec3 octahedral_decode(const Vec2& square, const OctahedralFrame& frame) {
  const Vec3 d = octahedral_decode(square);
  return frame.identity() ? d : frame.to_sphere(d);
}

}  // namespace spheremap
