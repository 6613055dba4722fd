// surface_distances: the distance to all of a surface and to its kept triangles from one set
// of queries, each figure bit for bit that of its own surface_distance call.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/surface_distance.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// The RMS figures bit for bit; each maximum within the tolerance of the separate call's
// (both are within it of the true maximum, found through other pieces: a piece cut for
// one figure measures both; refined_maximum.h).
void expect_max_near(double got, double expected) {
  EXPECT_NEAR(got, expected, std::max(0.05 * expected, 1e-3));
}

// `exact`: the maxima bit for bit too (the same queries in the same order).
void expect_same(const SurfaceDistance& got, const SurfaceDistance& expected, bool exact = false) {
  const auto expect_max = [exact](double got_max, double expected_max) {
    if (exact)
      EXPECT_EQ(got_max, expected_max);
    else
      expect_max_near(got_max, expected_max);
  };
  EXPECT_EQ(got.rms_a_to_b, expected.rms_a_to_b);
  expect_max(got.max_a_to_b, expected.max_a_to_b);
  EXPECT_EQ(got.rms_b_to_a, expected.rms_b_to_a);
  expect_max(got.max_b_to_a, expected.max_b_to_a);
  expect_max(got.hausdorff, expected.hausdorff);
  EXPECT_EQ(got.rms, expected.rms);
  EXPECT_EQ(got.diagonal, expected.diagonal);
  EXPECT_EQ(got.samples, expected.samples);
}

// A twisted torus against a wavy copy of it, with scattered triangles and whole patches left
// out (so that some vertices are used by left-out triangles alone).
TEST(SurfaceDistances, EachEqualsItsOwnSurfaceDistance) {
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

// One measure of a surface (its tree built once, its triangles copied: the caller's list
// is gone) answers a sequence of other surfaces and points as each fresh call does, bit for
// bit: what a remesh trying several frames relies on.
TEST(SurfaceMeasure, AnswersEachQueryOfASequenceAsAFreshCallDoes) {
  const PolygonMesh a = testing::twisted(testing::torus(32, 16), 0.7);
  const std::vector<Triangle> triangles = fan_triangulate(a).triangles;
  const SurfaceMeasure measure(a.positions, std::vector<Triangle>(triangles));
  std::vector<char> left_out(triangles.size(), 0);
  for (size_t k = 0; k < triangles.size(); k += 5) left_out[k] = 1;
  for (double wave : {0.01, 0.05, 0.2}) {
    PolygonMesh b = testing::icosphere(3);
    for (Vec3& p : b.positions) p = p * (1 + wave * std::sin(9 * p.z));
    const std::vector<Triangle> b_triangles = fan_triangulate(b).triangles;
    const SurfaceDistance one = measure.distance_to(b.positions, b_triangles, 2);
    expect_same(one, surface_distance(a.positions, triangles, b.positions, b_triangles, 2), true);
    EXPECT_GT(one.hausdorff, 0);
    const SurfaceDistances both = measure.distances_to(left_out, b.positions, b_triangles, 2);
    const SurfaceDistances fresh =
        surface_distances(a.positions, triangles, left_out, b.positions, b_triangles, 2);
    expect_same(both.all, fresh.all, true);
    expect_same(both.kept, fresh.kept, true);
    const PointDistances points = measure.point_distances(b.positions, 2);
    EXPECT_EQ(points.relative, point_distances(a.positions, triangles, b.positions, 2).relative);
  }
  EXPECT_THROW(measure.distances_to(std::vector<char>(3, 0), a.positions, triangles),
               std::invalid_argument);
}

// The largest of many points' distances, found without measuring each exactly, is the
// largest of point_distances' bit for bit, on any threads.
TEST(SurfaceMeasure, TheLargestPointDistanceIsTheLargestOfThePointDistances) {
  const PolygonMesh sphere = testing::icosphere(3);
  const std::vector<Triangle> triangles = fan_triangulate(sphere).triangles;
  const SurfaceMeasure measure(sphere.positions, triangles);
  std::vector<Vec3> points;
  for (int k = 0; k < 5000; ++k) {  // around the sphere, at radii 0.5 to 1.5
    const double t = 0.7 * k, z = std::fmod(0.37 * k, 2.0) - 1.0, r = std::sqrt(1 - z * z);
    points.push_back(Vec3{r * std::cos(t), r * std::sin(t), z} * (0.5 + std::fmod(0.013 * k, 1.0)));
  }
  const PointDistances all = measure.point_distances(points, 1);
  const double largest = *std::max_element(all.relative.begin(), all.relative.end());
  EXPECT_GT(largest, 0.1);
  for (int threads : {1, 2}) EXPECT_EQ(measure.largest_point_distance(points, threads), largest);
  EXPECT_EQ(measure.largest_point_distance({}, 1), 0.0);
}

// A measure that may give up: above the surfaces' Hausdorff distance it is the full
// measure exactly; below it, it stops once that far is found and says so.
TEST(SurfaceMeasure, GivesUpOnlyOnceTheDistanceFoundReachesIt) {
  const PolygonMesh sphere = testing::icosphere(3);
  const std::vector<Triangle> triangles = fan_triangulate(sphere).triangles;
  PolygonMesh spiked = sphere;
  spiked.positions[0] = spiked.positions[0] * 1.5;
  const SurfaceMeasure measure(sphere.positions, triangles);
  const SurfaceDistance full = measure.distance_to(spiked.positions, triangles, 1);
  ASSERT_GT(full.hausdorff, 0.1);
  EXPECT_FALSE(full.gave_up);
  const SurfaceDistance above =
      measure.distance_to(spiked.positions, triangles, 1, nullptr, 1.01 * full.hausdorff);
  EXPECT_FALSE(above.gave_up);
  EXPECT_EQ(above.hausdorff, full.hausdorff);
  EXPECT_EQ(above.rms, full.rms);
  EXPECT_EQ(above.hausdorff_at_most, full.hausdorff_at_most);
  const SurfaceDistance below =
      measure.distance_to(spiked.positions, triangles, 1, nullptr, 0.5 * full.hausdorff);
  EXPECT_TRUE(below.gave_up);
  EXPECT_FALSE(below.hausdorff_settled);
  EXPECT_GE(below.hausdorff, 0.5 * full.hausdorff);
  // The same with faces left out (the kept figure gives up).
  const std::vector<char> none_left_out(triangles.size(), 0);
  const SurfaceDistances both = measure.distances_to(none_left_out, spiked.positions, triangles, 1,
                                                     nullptr, 0.5 * full.hausdorff);
  EXPECT_TRUE(both.kept.gave_up);
  EXPECT_GE(both.kept.hausdorff, 0.5 * full.hausdorff);
  const SurfaceDistances kept_all = measure.distances_to(none_left_out, spiked.positions, triangles,
                                                         1, nullptr, 1.01 * full.hausdorff);
  EXPECT_FALSE(kept_all.kept.gave_up);
  EXPECT_EQ(kept_all.kept.hausdorff, full.hausdorff);
}

// A surface against itself settles at once: each triangle's corners lie on itself, the
// other surface's triangle nearest its centroid, and the distance to one triangle is
// largest at a corner of a piece (convex). A square split along one diagonal against the
// same square split along the other: every distance is 0, but a piece across the other's
// diagonal is never within one of its triangles and its Lipschitz bound stays over the
// tolerance down to the depth limit (1/256 of the square's side), so the maximum found (0)
// is said to be unsettled, with what it is at most (about that piece's size).
// A sphere with one spike settles (every other triangle's bound is under the spike's
// distance), within the tolerance.
TEST(SurfaceDistance, SaysWhatTheMaximumIsAtMostWhenItsBudgetRunsOut) {
  const PolygonMesh a = testing::icosphere(1);
  const std::vector<Triangle> triangles = fan_triangulate(a).triangles;
  const SurfaceDistance same = surface_distance(a.positions, triangles, a.positions, triangles, 1);
  EXPECT_LT(same.hausdorff, 1e-12);
  EXPECT_TRUE(same.hausdorff_settled);
  EXPECT_LE(same.hausdorff_at_most, 1e-3 + 1e-12);  // the tolerance: 0.1% of the diagonal
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<Triangle> one_way = {{0, 1, 2}, {0, 2, 3}}, other_way = {{0, 1, 3}, {1, 2, 3}};
  const SurfaceDistance across = surface_distance(square, one_way, square, other_way, 1);
  EXPECT_LT(across.hausdorff, 1e-12);
  EXPECT_FALSE(across.hausdorff_settled);
  EXPECT_GT(across.hausdorff_at_most, 1e-3);  // over the tolerance: the bound left open
  EXPECT_LT(across.hausdorff_at_most, 0.01);
  const PolygonMesh sphere = testing::icosphere(3);
  const std::vector<Triangle> sphere_triangles = fan_triangulate(sphere).triangles;
  PolygonMesh spiked = sphere;
  spiked.positions[0] = spiked.positions[0] * 1.5;
  const SurfaceDistance spike =
      surface_distance(sphere.positions, sphere_triangles, spiked.positions, sphere_triangles, 1);
  EXPECT_TRUE(spike.hausdorff_settled);
  EXPECT_GT(spike.hausdorff, 0.1);
  EXPECT_GE(spike.hausdorff_at_most, spike.hausdorff);
  EXPECT_LE(spike.hausdorff_at_most, 1.05 * spike.hausdorff + 1e-3);
}

// A large triangle over a surface that touches it only at its corners and its centroid
// (a remesh triangle across a hole's opening): every sample of the triangle lies on the
// surface, but its edge midpoints are a quarter of an edge from it. The maximum is found
// over the whole triangle: at least the midpoints' distance, at most what 20,301 points
// spread over the triangle see, plus the tolerance.
TEST(SurfaceDistance, TheMaximumIsOverTheWholeTriangleNotOnlyItsSamples) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.5, std::sqrt(0.75), 0};
  const Vec3 centre = (a + b + c) * (1.0 / 3);
  const std::vector<Vec3> big = {a, b, c};
  const std::vector<Triangle> one = {{0, 1, 2}};
  // Small triangles of the same plane at the corners and the centre.
  std::vector<Vec3> patches;
  std::vector<Triangle> patch_triangles;
  for (const Vec3& p : {a, b, c, centre}) {
    const auto base = static_cast<uint32_t>(patches.size());
    patches.insert(patches.end(),
                   {p + Vec3{-0.01, -0.01, 0}, p + Vec3{0.01, -0.01, 0}, p + Vec3{0, 0.01, 0}});
    patch_triangles.push_back({base, base + 1, base + 2});
  }
  const SurfaceDistance d = surface_distance(big, one, patches, patch_triangles, 1);
  // With the vertices alone sampled, the refinement still searches the whole triangle.
  const SurfaceDistance by_vertices =
      surface_distance(big, one, patches, patch_triangles, 1, nullptr, DistanceSamples::kVertices);
  const std::vector<Vec3> midpoints = {0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)};
  double midpoint_max = 0;
  for (double r : point_distances(patches, patch_triangles, midpoints, 1).relative)
    midpoint_max = std::max(midpoint_max, r);
  std::vector<Vec3> spread;
  const int steps = 200;
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; i + j <= steps; ++j)
      spread.push_back(a + (static_cast<double>(i) / steps) * (b - a) +
                       (static_cast<double>(j) / steps) * (c - a));
  double spread_max = 0;
  for (double r : point_distances(patches, patch_triangles, spread, 1).relative)
    spread_max = std::max(spread_max, r);
  // point_distances is relative to the patches' diagonal, surface_distance to the big one's.
  const double scale = point_distances(patches, patch_triangles, {}, 1).diagonal / d.diagonal;
  ASSERT_GT(midpoint_max * scale, 0.2);
  for (const SurfaceDistance& measured : {d, by_vertices}) {
    EXPECT_GE(measured.max_a_to_b, midpoint_max * scale - 1e-12);
    EXPECT_LE(measured.max_a_to_b, spread_max * scale * 1.06);
  }
  EXPECT_LT(d.max_b_to_a, 0.02);  // the patches stick out of the big triangle by 0.01
}

// DistanceSamples::kVertices: the RMS over each surface's vertices alone (each direction's
// equal to the one computed from point_distances of those vertices), the maximum the same
// as with centroids within the tolerance (both are within it of the true maximum).
TEST(SurfaceDistance, TheVerticesAloneGiveTheirOwnRmsAndTheSameMaximum) {
  const PolygonMesh a = testing::twisted(testing::torus(32, 16), 0.7);
  PolygonMesh b = a;
  for (Vec3& p : b.positions) p = p + Vec3{0.03 * std::sin(5 * p.y), 0.02 * std::cos(7 * p.x), 0};
  const std::vector<Triangle> a_triangles = fan_triangulate(a).triangles;
  const std::vector<Triangle> b_triangles = fan_triangulate(b).triangles;
  const SurfaceDistance both = surface_distance(a.positions, a_triangles, b.positions, b_triangles);
  const SurfaceDistance vertices = surface_distance(
      a.positions, a_triangles, b.positions, b_triangles, 2, nullptr, DistanceSamples::kVertices);
  EXPECT_EQ(vertices.samples, a.positions.size() + b.positions.size());
  EXPECT_EQ(both.samples, vertices.samples + a_triangles.size() + b_triangles.size());
  const auto rms_of = [](const std::vector<double>& relative) {
    double sum = 0;
    for (double r : relative) sum += r * r;
    return std::sqrt(sum / double(relative.size()));
  };
  // point_distances measures to a; a's vertices to b: b's measure, relative to b's diagonal.
  const PointDistances b_to_a = point_distances(a.positions, a_triangles, b.positions);
  const PointDistances a_to_b = point_distances(b.positions, b_triangles, a.positions);
  const double scale = a_to_b.diagonal / vertices.diagonal;
  ASSERT_GT(rms_of(b_to_a.relative), 0.001);
  EXPECT_NEAR(vertices.rms_b_to_a, rms_of(b_to_a.relative), 1e-9);
  EXPECT_NEAR(vertices.rms_a_to_b, rms_of(a_to_b.relative) * scale, 1e-9);
  EXPECT_NE(vertices.rms, both.rms);
  expect_max_near(vertices.max_a_to_b, both.max_a_to_b);
  expect_max_near(vertices.max_b_to_a, both.max_b_to_a);
  expect_max_near(vertices.hausdorff, both.hausdorff);
  EXPECT_EQ(vertices.diagonal, both.diagonal);
}

}  // namespace
}  // namespace spheremap
