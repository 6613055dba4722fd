#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/map/map_check.h"
#include "core/map/stretch_newton.h"
#include "core/map/stretch_optimizer.h"
#include "core/mesh/sphere_geometry.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(StretchNewton, FirstCubicRootFindsTheFirstSignChangeOnly) {
  // (0.5 - t)(t + 1)(2 - t) = 1 - 1.5 t - 1.5 t^2 + t^3: roots -1, 0.5, 2.
  EXPECT_NEAR(first_cubic_root(1, -1.5, -1.5, 1, 3), 0.5, 1e-12);
  EXPECT_EQ(first_cubic_root(1, -1.5, -1.5, 1, 0.4), 0.4);      // no root before the limit
  EXPECT_EQ(first_cubic_root(1, 0, 1, 0, 10), 10);              // 1 + t^2 never vanishes
  EXPECT_NEAR(first_cubic_root(1, -4, 0, 0, 10), 0.25, 1e-12);  // linear
}

// A CAD cylinder (256 sides, one band of side slivers, fan caps), centred, so its central
// projection is a fold-free start. The optimum moves the 512 rim vertices together;
// single-vertex sweeps crawl there (measured: 60 sweeps leave energy 1.88, converging
// takes 395 sweeps to 1.768), 60 sweeps then Newton steps reach 1.769.
TEST(StretchOptimizer, NewtonStepsConvergeWhereSweepsCrawl) {
  std::vector<std::array<double, 2>> circle;
  for (int k = 0; k < 256; ++k)
    circle.push_back({std::cos(2 * M_PI * k / 256), std::sin(2 * M_PI * k / 256)});
  const PolygonMesh mesh = testing::prism(circle, 3, true);
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  std::vector<Vec3> start(mesh.vertex_count());
  for (size_t v = 0; v < start.size(); ++v) start[v] = normalized_or(mesh.positions[v], Vec3{});
  ASSERT_TRUE(check_map(start, triangles).bijective);

  auto optimized = [&](size_t sweeps, size_t newton_max_vertices, std::vector<Vec3>& q) {
    q = start;
    return optimize_stretch(mesh.positions, triangles, q,
                            {.max_sweeps = sweeps,
                             .relative_decrease = 1e-5,
                             .newton_max_vertices = newton_max_vertices},
                            [] { return false; });
  };
  std::vector<Vec3> swept, newton, converged;
  const StretchStats sweeps_only = optimized(60, 0, swept);
  const StretchStats with_newton = optimized(60, 1000, newton);
  const StretchStats reference = optimized(3000, 0, converged);
  EXPECT_EQ(sweeps_only.newton_steps, 0u);
  EXPECT_GT(with_newton.newton_steps, 0u);
  // Newton steps close at least 90% of the gap the 60 sweeps leave.
  EXPECT_LT(with_newton.final_energy - reference.final_energy,
            0.1 * (sweeps_only.final_energy - reference.final_energy));
  EXPECT_TRUE(check_map(newton, triangles).bijective);
  for (const Vec3& p : newton) EXPECT_NEAR(norm(p), 1.0, 1e-12);
}

}  // namespace
}  // namespace spheremap
