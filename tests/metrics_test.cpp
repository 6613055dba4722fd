#include <gtest/gtest.h>

#include <cmath>

#include "core/metrics.h"
#include "core/spherical_map.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(Metrics, SphereMappedToItselfIsNearlyUndistorted) {
  const PolygonMesh sphere = testing::icosphere(3);
  const auto tris = oriented_triangles(sphere).triangles;
  const QualityMetrics m = compute_metrics(sphere.positions, sphere.positions, tris);
  EXPECT_EQ(m.skipped_triangles, 0u);
  EXPECT_LT(m.dilatation.max, 1.0 + 1e-9);  // chord triangles are the triangles
  EXPECT_LT(m.angle_error_degrees, 1e-9);
  EXPECT_LT(m.area_log_ratio.mean, 0.05);  // spherical vs flat area only
  EXPECT_NEAR(m.stretch_l2, 1.0, 1e-9);
}

TEST(Metrics, AffineStretchGivesItsDilatation) {
  // Surface = sphere squashed by 2 along z: triangles stretch, K reflects the squash.
  const PolygonMesh sphere = testing::icosphere(3);
  std::vector<Vec3> surface = sphere.positions;
  for (Vec3& p : surface) p.z *= 0.5;
  const auto tris = oriented_triangles(sphere).triangles;
  const QualityMetrics m = compute_metrics(surface, sphere.positions, tris);
  EXPECT_GT(m.dilatation.max, 1.9);
  EXPECT_LT(m.dilatation.max, 2.0 + 1e-6);
  EXPECT_GT(m.dilatation.mean, 1.2);
  EXPECT_GT(m.stretch_l2, 1.0);
  EXPECT_GT(m.angle_error_degrees, 1.0);
}

TEST(Metrics, FoldedTrianglesAreSkippedNotNaN) {
  const PolygonMesh sphere = testing::icosphere(2);
  std::vector<Vec3> map = sphere.positions;
  map[0] = -map[0];
  const auto tris = oriented_triangles(sphere).triangles;
  const QualityMetrics m = compute_metrics(sphere.positions, map, tris);
  EXPECT_GT(m.skipped_triangles, 0u);
  EXPECT_TRUE(std::isfinite(m.dilatation.mean));
  EXPECT_TRUE(std::isfinite(m.area_log_ratio.max));
}

}  // namespace
}  // namespace spheremap
