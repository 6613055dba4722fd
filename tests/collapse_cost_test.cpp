#include "core/map/collapse_cost.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace spheremap {
namespace {

// An open tube of `around` x `rings` vertices (id = ring * around + i), radius 1, rings
// `spacing` apart along z, each quad split in two.
struct Tube {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

Tube open_tube(uint32_t around, uint32_t rings, double spacing) {
  Tube tube;
  for (uint32_t j = 0; j < rings; ++j)
    for (uint32_t i = 0; i < around; ++i) {
      const double angle = 2 * std::numbers::pi * i / around;
      tube.positions.push_back({std::cos(angle), std::sin(angle), spacing * j});
    }
  for (uint32_t j = 0; j + 1 < rings; ++j)
    for (uint32_t i = 0; i < around; ++i) {
      const uint32_t a = j * around + i, b = j * around + (i + 1) % around;
      tube.triangles.push_back({a, b, b + around});
      tube.triangles.push_back({a, b + around, a + around});
    }
  return tube;
}

TEST(CollapseCost, FlatCollapsesCostTheirSquaredEdgeLengthOnly) {
  // A unit square fanned around its centre 4: every plane is z = 0.
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0}};
  const std::vector<Triangle> t = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const CollapseCost cost(x, t);
  const double to_corner = cost(4, 0), to_side = cost(0, 1);
  EXPECT_GT(to_corner, 0);
  EXPECT_NEAR(to_side / to_corner, 1.0 / 0.5, 1e-9);  // |01|^2 = 1, |40|^2 = 0.5
}

TEST(CollapseCost, ALongTubeCollapsesAlongItsLengthBeforeAroundIt) {
  // Edges around (0.77) are shorter than along (2): a shortest-edge order would close
  // the tube to a needle first; the plane error keeps its cross-section.
  const Tube tube = open_tube(8, 3, 2.0);
  CollapseCost cost(tube.positions, tube.triangles);
  const uint32_t u = 8, around = 9, along = 16;  // middle ring
  EXPECT_LT(squared_norm(tube.positions[u] - tube.positions[around]),
            squared_norm(tube.positions[u] - tube.positions[along]));
  EXPECT_LT(100 * cost(u, along), cost(u, around));
  // Once vertex 9 stands for u's planes too, moving its neighbour 10 onto it also costs
  // 9's distance from u's other facet plane (15, 8, 16, 23).
  const double before = cost(10, around);
  cost.merge(u, around);
  EXPECT_GT(cost(10, around), 1.2 * before);
}

}  // namespace
}  // namespace spheremap
