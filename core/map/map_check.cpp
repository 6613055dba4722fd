#include "core/map/map_check.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/sphere_geometry.h"

namespace spheremap {

MapCheck check_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles) {
  MapCheck check;
  check.triangles = triangles.size();
  check.min_signed_area = INFINITY;
  for (const Triangle& t : triangles) {
    const Vec3 &a = sphere[t[0]], &b = sphere[t[1]], &c = sphere[t[2]];
    const double area = spherical_area_of_directions(a, b, c);
    if (!is_valid_triangle(a, b, c))
      ++check.folds;
    else if (area < kDegenerateArea)
      ++check.degenerate;
    check.signed_area_sum += area;
    check.min_signed_area = std::min(check.min_signed_area, area);
  }
  // With no fold, the triangles cover the sphere a whole number of times, so the sum is
  // 4 pi times that number: the sum only has to tell 4 pi from 8 pi (covered twice) or 0.
  // 1e-5 of 4 pi leaves room for rounding: areas are of the corners' directions, so
  // float32 positions off the unit sphere by 6e-8 cost nothing beyond double's rounding.
  check.bijective =
      check.folds == 0 && std::abs(check.signed_area_sum - 4 * M_PI) < 1e-5 * 4 * M_PI;
  return check;
}

void add_check(MapCheck& total, const MapCheck& part) {
  total.triangles += part.triangles;
  total.folds += part.folds;
  total.nonconvex_polygons += part.nonconvex_polygons;
  total.degenerate += part.degenerate;
  total.signed_area_sum += part.signed_area_sum;
  total.min_signed_area = std::min(total.min_signed_area, part.min_signed_area);
  total.bijective = total.bijective && part.bijective;
}

MapCheck verify_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles,
                    const PolygonMesh& mesh, bool inward) {
  MapCheck check = check_map(sphere, triangles);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    const size_t d = face.size();
    if (d < 4) continue;
    for (size_t k = 0; k < d; ++k) {
      const Vec3& prev = sphere[face[(k + d - 1) % d]];
      const Vec3& next = sphere[face[(k + 1) % d]];
      const Vec3& at = sphere[face[k]];
      if (!(inward ? is_valid_triangle(next, at, prev) : is_valid_triangle(prev, at, next))) {
        ++check.nonconvex_polygons;
        break;
      }
    }
  }
  return check;
}

}  // namespace spheremap
