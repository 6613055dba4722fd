// The remesh grid of each part: samples per unit area alike while the parts' samples
// together fit kPartSampleBudget grids of the asked resolution, scaled down together past it.
#include <gtest/gtest.h>

#include <vector>

#include "core/map/map_parts.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/part_grids.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

double samples(const std::vector<int>& grids) {
  double total = 0;
  for (int grid : grids) total += (grid + 1.0) * (grid + 1.0);
  return total;
}

TEST(PartGrids, TheLargestPartGetsTheResolutionAndSmallerOnesTheirAreasRoot) {
  const std::vector<double> areas = {4.0, 1.0, 0.25, 1e-9};
  EXPECT_EQ(part_grids(128, areas), (std::vector<int>{128, 64, 32, 8}));
  EXPECT_EQ(part_grids(4, areas), (std::vector<int>{4, 4, 4, 4}));  // never above N
  EXPECT_EQ(part_grids(64, std::vector<double>{0.0, 0.0}), (std::vector<int>{64, 64}));
}

TEST(PartGrids, ManyEqualPartsShareTheBudgetAlike) {
  const std::vector<double> areas(500, 1.0);
  const std::vector<int> grids = part_grids(256, areas);
  const double budget = kPartSampleBudget * 257.0 * 257.0;
  EXPECT_LE(samples(grids), budget);
  EXPECT_GT(samples(grids), 0.7 * budget);  // the budget is used, not wasted
  for (int grid : grids) {
    EXPECT_EQ(grid, grids[0]);
    EXPECT_EQ(grid % 2, 0);
  }
  EXPECT_LT(grids[0], 256);
}

// One large part among a cloud of fragments: it keeps the largest grid, every grid shrinks
// by the same factor, and fragments go down to the octahedron (N = 2), no further.
TEST(PartGrids, FragmentsShrinkToTheOctahedronAndTheLargestStaysLargest) {
  std::vector<double> areas(20000, 1e-4);
  areas.insert(areas.begin(), 1.0);
  const std::vector<int> grids = part_grids(256, areas);
  EXPECT_LE(samples(grids), kPartSampleBudget * 257.0 * 257.0);
  EXPECT_EQ(*std::max_element(grids.begin(), grids.end()), grids[0]);
  EXPECT_GE(grids[0], 200);
  for (size_t k = 1; k < grids.size(); ++k) EXPECT_EQ(grids[k], 2);
  // So many parts that even their octahedra pass the budget: each stays an octahedron.
  const std::vector<int> many = part_grids(16, std::vector<double>(5000, 1.0));
  for (int grid : many) EXPECT_EQ(grid, 2);
}

// End to end: 300 equal closed parts remeshed at 64 hold about the budget's samples, where
// a full grid each would be 300 times one.
TEST(PartGrids, ARemeshOfManyEqualPartsHoldsTheBudget) {
  std::vector<std::pair<PolygonMesh, Vec3>> pieces;
  for (int k = 0; k < 300; ++k)
    pieces.push_back({testing::icosphere(1), {3.0 * (k % 20), 3.0 * (k / 20), 0}});
  PolygonMesh input = testing::assembled(pieces);
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 300u);
  const RemeshAsset remesh = remesh_asset(mapped, 64);
  EXPECT_TRUE(remesh.metrics["closed_genus0"]);
  EXPECT_LE(remesh.metrics["samples"].get<double>(), kPartSampleBudget * 65 * 65);
  EXPECT_EQ(remesh.metrics["parts"].size(), 300u);
}

}  // namespace
}  // namespace spheremap
