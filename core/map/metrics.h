// Quality of a spherical map (ALGORITHM §C), per triangle, aggregated area-weighted
// (weights = surface area of the input triangle):
//   area:   r = (spherical area / 4 pi) / (surface area / total area); |log r|
//   angle:  the affine map from the surface triangle to the sphere's chord triangle has
//           singular values s1 >= s2; dilatation K = s1 / s2 (1 = conformal); mean
//           absolute corner-angle error between the two triangles, in degrees
//   stretch (Sander et al. 2001): singular values of the map from the chord triangles,
//           scaled to the surface's total area, back to the surface; L2 = area-weighted
//           RMS of sqrt((g1^2 + g2^2) / 2), Linf = max of the larger one. Both are >= 1.
#pragma once

#include <cmath>
#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

struct DistortionSummary {
  double mean = 0, p99 = 0, max = 0;
};

struct QualityMetrics {
  DistortionSummary area_log_ratio;
  DistortionSummary dilatation;
  double angle_error_degrees = 0;
  double stretch_l2 = 0, stretch_linf = 0;
  size_t measured_triangles = 0;
  size_t skipped_triangles = 0;  // zero surface or spherical area: no finite ratio
};

// Triangles oriented so a valid map has positive determinants. threads: 0 = all cores;
// the metrics are the same for any value. `sphere_share`: the spherical area the triangles
// cover, 4 pi when they are the whole mesh (less when some faces are left out of the
// measure: an area ratio compares each triangle's share of it to its share of the surface).
QualityMetrics compute_metrics(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                               std::span<const Triangle> triangles, int threads = 0,
                               double sphere_share = 4 * M_PI);

}  // namespace spheremap
