// The verdict on a spherical map (ALGORITHM §B1): folds, degenerate triangles, and the
// signed area sum that catches a map wrapping the sphere more than once.
#pragma once

#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

// A spherical triangle smaller than this share of the unit sphere's area is reported as
// degenerate: below it, float64 positions barely separate the corners.
inline constexpr double kDegenerateArea = 1e-14;

struct MapCheck {
  size_t triangles = 0;
  size_t folds = 0;  // triangles failing the §B1 validity test (NaN included)
  // Faces of 4+ corners with a corner turning the wrong way on the sphere: not a fold
  // (the faces' fan triangles are valid), but a consumer triangulating such a face
  // differently can see an overlap there. Information, not part of the verdict.
  size_t nonconvex_polygons = 0;
  size_t degenerate = 0;  // valid triangles with spherical area below kDegenerateArea
  double signed_area_sum = 0;
  double min_signed_area = 0;
  bool bijective = false;  // folds == 0 and signed areas sum to 4 pi
};

// Triangles oriented so that a valid map has positive determinants. Checks triangles
// only (nonconvex_polygons stays 0): enough for a level of the hierarchy.
MapCheck check_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles);

// Adds `part` (a check of one part of an asset on its own sphere) into `total`: counts
// summed, the smallest area kept, bijective only while every part's is. Start `total`
// with min_signed_area = INFINITY and bijective = true.
void add_check(MapCheck& total, const MapCheck& part);

// The verdict on a whole mesh: check_map on its fan triangles, plus the count of
// polygons that are not convex on the sphere. `inward`: the faces run clockwise.
MapCheck verify_map(std::span<const Vec3> sphere, std::span<const Triangle> triangles,
                    const PolygonMesh& mesh, bool inward);

}  // namespace spheremap
