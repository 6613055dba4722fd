#include <gtest/gtest.h>

#include <cmath>

#include "core/map/metrics.h"
#include "core/map/spherical_map.h"
#include "core/mesh/sphere_geometry.h"
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

TEST(Metrics, AreTheSameForAnyThreadCount) {
  // 81,920 triangles: two of compute_metrics' blocks, each computed in parallel and summed
  // in order, so 1 and 2 threads must give the same bits; a fold adds skipped triangles.
  const PolygonMesh sphere = testing::icosphere(6);
  const PolygonMesh surface = testing::swirled(testing::scaled(sphere, {1, 1, 0.5}), 1.0);
  std::vector<Vec3> map = sphere.positions;
  map[map.size() - 1] = -map[map.size() - 1];
  const auto tris = oriented_triangles(sphere).triangles;
  ASSERT_GT(tris.size(), size_t{1} << 16);
  const QualityMetrics one = compute_metrics(surface.positions, map, tris, 1);
  const QualityMetrics two = compute_metrics(surface.positions, map, tris, 2);
  EXPECT_GT(one.skipped_triangles, 0u);
  EXPECT_EQ(one.skipped_triangles, two.skipped_triangles);
  EXPECT_EQ(one.measured_triangles, two.measured_triangles);
  EXPECT_EQ(one.stretch_l2, two.stretch_l2);
  EXPECT_EQ(one.stretch_linf, two.stretch_linf);
  EXPECT_EQ(one.angle_error_degrees, two.angle_error_degrees);
  for (auto summary : {&QualityMetrics::area_log_ratio, &QualityMetrics::dilatation}) {
    EXPECT_EQ((one.*summary).mean, (two.*summary).mean);
    EXPECT_EQ((one.*summary).p99, (two.*summary).p99);
    EXPECT_EQ((one.*summary).max, (two.*summary).max);
  }
  EXPECT_GT(one.dilatation.mean, 1.0);
}

}  // namespace
}  // namespace spheremap

namespace spheremap {
namespace {

TEST(SphereGeometry, OrientationOfSliversIsDecidedBeyondDoubleRounding) {
  // A sliver of beast's map: +9.2e-18 in double, -1.36e-17 exactly (a fold).
  const Vec3 a{0.54907006529461355, 0.33840320950038827, -0.76420241506894315};
  const Vec3 b{0.54907005443104517, 0.33840321876043317, -0.76420241877376149};
  const Vec3 c{0.54907000758368107, 0.33840325773854812, -0.76420243517277187};
  EXPECT_GT(triple_product(a, b, c), 0);  // what double says
  EXPECT_FALSE(is_valid_triangle(a, b, c));
  // The other way round double says -9.2e-18: invalid without a second look (the test
  // is conservative: valid only when certain).
  EXPECT_FALSE(is_valid_triangle(a, c, b));
  // Ordinary triangles keep the fast path's answer.
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_TRUE(is_valid_triangle(x, y, z));
  EXPECT_FALSE(is_valid_triangle(x, z, y));
}

TEST(SphereGeometry, AreaWeightMatchesSphericalAreaAtEveryScale) {
  const Vec3 a = normalized_or({1, 0, 0}, {}), b0 = normalized_or({1, 1, 0}, {}),
             c0 = normalized_or({1, 0, 1}, {});
  for (double s : {1.0, 0.5, 0.1, 1e-3, 1e-6, 1e-9}) {
    const Vec3 b = normalized_or(a + s * (b0 - a), a), c = normalized_or(a + s * (c0 - a), a);
    const double exact = std::abs(spherical_area(a, b, c));
    EXPECT_NEAR(unsigned_area_weight(a, b, c), exact, 2e-8 * exact) << "scale " << s;
    EXPECT_NEAR(unsigned_area_weight(a, c, b), exact, 2e-8 * exact) << "reversed, scale " << s;
  }
  // Larger than a hemisphere's worth of angle: the atan2 path.
  const Vec3 p{1, 0, 0}, q{0, 1, 0}, r{0, 0, 1};
  EXPECT_NEAR(unsigned_area_weight(p, q, r), M_PI / 2, 1e-15);
}

}  // namespace
}  // namespace spheremap
