// surface_distances: the distance to all of a surface and to its kept triangles from one set
// of queries, each figure bit for bit that of its own surface_distance call.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/surface_distance.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

void expect_same(const SurfaceDistance& got, const SurfaceDistance& expected) {
  EXPECT_EQ(got.rms_a_to_b, expected.rms_a_to_b);
  EXPECT_EQ(got.max_a_to_b, expected.max_a_to_b);
  EXPECT_EQ(got.rms_b_to_a, expected.rms_b_to_a);
  EXPECT_EQ(got.max_b_to_a, expected.max_b_to_a);
  EXPECT_EQ(got.hausdorff, expected.hausdorff);
  EXPECT_EQ(got.rms, expected.rms);
  EXPECT_EQ(got.diagonal, expected.diagonal);
  EXPECT_EQ(got.samples, expected.samples);
}

// A twisted torus against a wavy copy of it, with scattered triangles and whole patches left
// out (so that some vertices are used by left-out triangles alone).
TEST(SurfaceDistances, EachEqualsItsOwnSurfaceDistanceBitForBit) {
  const PolygonMesh a = testing::twisted(testing::torus(32, 16), 0.7);
  const std::vector<Triangle> triangles = fan_triangulate(a).triangles;
  std::vector<char> left_out(triangles.size(), 0);
  std::vector<Triangle> kept;
  for (size_t k = 0; k < triangles.size(); ++k) {
    left_out[k] = k % 7 == 3 || (k / 40) % 5 == 0;
    if (!left_out[k]) kept.push_back(triangles[k]);
  }
  PolygonMesh b = a;
  for (Vec3& p : b.positions) p = p + Vec3{0.03 * std::sin(5 * p.y), 0.02 * std::cos(7 * p.x), 0};
  const std::vector<Triangle> b_triangles = fan_triangulate(b).triangles;
  const SurfaceDistances both =
      surface_distances(a.positions, triangles, left_out, b.positions, b_triangles, 2);
  expect_same(both.all, surface_distance(a.positions, triangles, b.positions, b_triangles, 2));
  expect_same(both.kept, surface_distance(a.positions, kept, b.positions, b_triangles, 2));
  EXPECT_LT(both.kept.samples, both.all.samples);
  EXPECT_GT(both.kept.hausdorff, both.all.hausdorff);  // b covers what a's kept part lacks
}

TEST(SurfaceDistances, RefusesALeftOutListOfAnotherLength) {
  const PolygonMesh a = testing::icosphere(2);
  const std::vector<Triangle> triangles = fan_triangulate(a).triangles;
  const std::vector<char> short_list(triangles.size() - 1, 0);
  EXPECT_THROW(surface_distances(a.positions, triangles, short_list, a.positions, triangles),
               std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
