// The verdict on a spherical map (ALGORITHM §B1): folds, degenerate triangles, and the
// signed area sum that catches a map wrapping the sphere more than once.
#pragma once

#include <span>

#include "core/mesh.h"

namespace spheremap {

// A spherical triangle smaller than this share of the unit sphere's area is reported as
// degenerate: below it, float64 positions barely separate the corners.
inline constexpr double kDegenerateArea = 1e-14;

struct MapCheck {
  size_t triangles = 0;
  size_t folds = 0;       // triangles failing the §B1 validity test (NaN included)
  size_t degenerate = 0;  // valid triangles with spherical area below kDegenerateArea
  double signed_area_sum = 0;
  double min_signed_area = 0;
  bool bijective = false;  // folds == 0 and signed areas sum to 4 pi
};

// Triangles oriented so that a valid map has positive determinants.
MapCheck check_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles);

}  // namespace spheremap
