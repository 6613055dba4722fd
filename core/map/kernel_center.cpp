#include "core/map/kernel_center.h"

#include <cmath>
#include <vector>

#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// Half-plane a x + b y + c >= r sqrt(a^2 + b^2) in the gnomonic plane coordinates (x, y).
struct HalfPlane {
  double a, b, c, length;
};

// Solves the 3x3 system rows (a, b, -length) (x, y, r) = -c by Cramer's rule.
bool solve3(const HalfPlane& p, const HalfPlane& q, const HalfPlane& s, double out[3]) {
  const double m[3][3] = {{p.a, p.b, -p.length}, {q.a, q.b, -q.length}, {s.a, s.b, -s.length}};
  const double rhs[3] = {-p.c, -q.c, -s.c};
  auto det3 = [](const double k[3][3]) {
    return k[0][0] * (k[1][1] * k[2][2] - k[1][2] * k[2][1]) -
           k[0][1] * (k[1][0] * k[2][2] - k[1][2] * k[2][0]) +
           k[0][2] * (k[1][0] * k[2][1] - k[1][1] * k[2][0]);
  };
  const double d = det3(m);
  if (!(std::abs(d) > 1e-300)) return false;
  for (int col = 0; col < 3; ++col) {
    double k[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) k[r][c] = c == col ? rhs[r] : m[r][c];
    out[col] = det3(k) / d;
  }
  return true;
}

}  // namespace

std::optional<Vec3> kernel_center(std::span<const Vec3> ring, const Vec3& center) {
  const size_t m = ring.size();
  if (m < 3 || m > kKernelCenterMaxCorners) return std::nullopt;
  for (const Vec3& r : ring)
    if (!(dot(r, center) > 1e-12)) return std::nullopt;
  // Orthonormal frame (e1, e2) of the tangent plane at center.
  const Vec3 helper = std::abs(center.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized_or(cross(center, helper), Vec3{});
  const Vec3 e2 = cross(center, e1);
  std::vector<HalfPlane> planes(m);
  double scale = 0;  // normalizes the constraints so tolerances are relative
  for (size_t i = 0; i < m; ++i) {
    const Vec3 n = cross(ring[i], ring[(i + 1) % m]);
    // p = center + x e1 + y e2: p . n = c + a x + b y
    planes[i] = {dot(e1, n), dot(e2, n), dot(center, n), 0};
    planes[i].length = std::hypot(planes[i].a, planes[i].b);
    if (!(planes[i].length > 0)) return std::nullopt;
    scale = std::max(scale, planes[i].length);
  }
  double best_r = 0, best_x = 0, best_y = 0;
  bool found = false;
  for (size_t i = 0; i < m; ++i)
    for (size_t j = i + 1; j < m; ++j)
      for (size_t k = j + 1; k < m; ++k) {
        double s[3];
        if (!solve3(planes[i], planes[j], planes[k], s) || !(s[2] > best_r)) continue;
        bool feasible = true;
        for (size_t t = 0; t < m && feasible; ++t) {
          const HalfPlane& h = planes[t];
          feasible = h.a * s[0] + h.b * s[1] + h.c >= s[2] * h.length - 1e-12 * scale * s[2];
        }
        if (feasible) best_r = s[2], best_x = s[0], best_y = s[1], found = true;
      }
  if (!found) return std::nullopt;
  return normalized_or(center + best_x * e1 + best_y * e2, center);
}

}  // namespace spheremap
