#include "core/map_check.h"

#include <cmath>

#include "core/sphere_geometry.h"

namespace spheremap {

MapCheck check_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles) {
  MapCheck check;
  check.triangles = triangles.size();
  check.min_signed_area = INFINITY;
  for (const Triangle& t : triangles) {
    const Vec3 &a = sphere[t[0]], &b = sphere[t[1]], &c = sphere[t[2]];
    const double area = spherical_area(a, b, c);
    if (!is_valid_triangle(a, b, c))
      ++check.folds;
    else if (area < kDegenerateArea)
      ++check.degenerate;
    check.signed_area_sum += area;
    check.min_signed_area = std::min(check.min_signed_area, area);
  }
  check.bijective =
      check.folds == 0 && std::abs(check.signed_area_sum - 4 * M_PI) < 1e-6 * 4 * M_PI;
  return check;
}

}  // namespace spheremap
