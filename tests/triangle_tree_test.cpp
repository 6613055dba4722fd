// TriangleTree against brute force (every triangle): the same least squared distance for
// every query, and an answer (point, triangle) that attains it, on generated meshes, for
// random points and points on corners, edges and faces (where several triangles tie).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/triangle_tree.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using namespace spheremap::testing;

double brute_force(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                   const Vec3& p) {
  double best = std::numeric_limits<double>::max();
  for (const Triangle& t : triangles)
    best = std::min(
        best, squared_norm(
                  closest_on_triangle(p, positions[t[0]], positions[t[1]], positions[t[2]]) - p));
  return best;
}

// Queries near and on the mesh: random points in its box grown by half, its corners, edge
// midpoints, centroids, and centroids pushed off the surface either way.
std::vector<Vec3> queries(const std::vector<Vec3>& positions,
                          const std::vector<Triangle>& triangles, unsigned seed) {
  AxisBox box;
  for (const Vec3& p : positions) box.add(p);
  const Vec3 size = box.hi - box.lo;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-0.25, 1.25);
  std::vector<Vec3> out;
  for (int k = 0; k < 2000; ++k)
    out.push_back({box.lo.x + size.x * unit(rng), box.lo.y + size.y * unit(rng),
                   box.lo.z + size.z * unit(rng)});
  for (const Vec3& p : positions) out.push_back(p);
  for (const Triangle& t : triangles) {
    const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    const Vec3 centroid = (a + b + c) * (1.0 / 3), normal = cross(b - a, c - a);
    out.push_back((a + b) * 0.5);
    out.push_back(centroid);
    out.push_back(centroid + normal * 0.3);
    out.push_back(centroid - normal * 0.3);
  }
  return out;
}

void expect_as_brute_force(const PolygonMesh& mesh, unsigned seed) {
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  const TriangleTree tree(mesh.positions, triangles);
  size_t checked = 0;
  for (const Vec3& p : queries(mesh.positions, triangles, seed)) {
    const TriangleTree::Closest answer = tree.closest(p);
    ASSERT_EQ(answer.squared_distance, brute_force(mesh.positions, triangles, p))
        << "query " << p.x << " " << p.y << " " << p.z;
    ASSERT_LT(answer.triangle, triangles.size());
    const Triangle& t = triangles[answer.triangle];
    const Vec3 point =
        closest_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    ASSERT_EQ(answer.point, point);
    ASSERT_EQ(answer.squared_distance, squared_norm(point - p));
    ++checked;
  }
  EXPECT_GT(checked, 2000u);
}

// Corners nearly on one line (pytorch3d's test OBJ: 0.1 steps that rounding bends): the
// barycentric coordinates are noise there, and the point they gave could lie anywhere in
// the plane. The answer must be the nearest point of the edges, as dense samples tell.
TEST(ClosestOnTriangle, OfCornersNearlyOnALineIsOnItsEdges) {
  const Vec3 a{0.1, 0.2, 0.3}, b{0.2, 0.3, 0.4}, c{0.4, 0.5, 0.6};
  std::mt19937 random(77);
  std::uniform_real_distribution<> unit(-0.2, 0.7);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{unit(random), unit(random), unit(random)};
    const Vec3 q = closest_on_triangle(p, a, b, c);
    double nearest = INFINITY;
    for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      for (int k = 0; k <= 4000; ++k)
        nearest = std::min(nearest, norm(from + (to - from) * (k / 4000.0) - p));
    ASSERT_LE(norm(q - p), nearest + 1e-9) << i;
    ASSERT_GE(norm(q - p), nearest - 1e-4) << i;
  }
}

TEST(TriangleTree, AnswersAsBruteForceOnASphere) {
  expect_as_brute_force(icosphere(3), 1);
}

TEST(TriangleTree, AnswersAsBruteForceOnATwistedTorus) {
  expect_as_brute_force(twisted(torus(24, 12), 0.7), 2);
}

TEST(TriangleTree, AnswersAsBruteForceOnAFlatSquashedShape) {
  // Thin boxes along one axis: many children boxes at equal distance from a query.
  expect_as_brute_force(scaled(quad_sphere(6), {1, 1, 1e-3}), 3);
}

// Leaving triangles out of the search answers as a tree of the rest would: as brute force
// over the kept triangles, for the same queries (on and beside the left-out ones too).
void expect_leaving_out_as_brute_force(const PolygonMesh& mesh, unsigned seed) {
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  std::vector<char> left_out(triangles.size(), 0);
  std::vector<Triangle> kept;
  for (size_t k = 0; k < triangles.size(); ++k) {
    left_out[k] = k % 7 == 3 || (k / 40) % 5 == 0;  // scattered triangles and whole patches
    if (!left_out[k]) kept.push_back(triangles[k]);
  }
  const TriangleTree tree(mesh.positions, triangles);
  size_t nearest_left_out = 0;
  for (const Vec3& p : queries(mesh.positions, triangles, seed)) {
    const TriangleTree::Closest answer = tree.closest(p, left_out);
    ASSERT_EQ(answer.squared_distance, brute_force(mesh.positions, kept, p))
        << "query " << p.x << " " << p.y << " " << p.z;
    ASSERT_FALSE(left_out[answer.triangle]);
    nearest_left_out += left_out[tree.closest(p).triangle];
  }
  EXPECT_GT(nearest_left_out, 1000u);  // the queries that a left-out triangle would answer
}

TEST(TriangleTree, LeavesTrianglesOutAsBruteForceOverTheRest) {
  expect_leaving_out_as_brute_force(icosphere(3), 4);
  expect_leaving_out_as_brute_force(twisted(torus(24, 12), 0.7), 5);
}

TEST(TriangleTree, LeavingEveryTriangleOutAnswersTheLargestDistance) {
  const PolygonMesh mesh = icosphere(1);
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  const TriangleTree tree(mesh.positions, triangles);
  const std::vector<char> all(triangles.size(), 1);
  EXPECT_EQ(tree.closest({1, 2, 3}, all).squared_distance, std::numeric_limits<double>::max());
}

TEST(TriangleTree, KeepsNoReferenceToItsInput) {
  const PolygonMesh mesh = icosphere(2);
  std::vector<Vec3> positions = mesh.positions;
  std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  const TriangleTree tree(positions, triangles);
  const Vec3 p{2, 0.1, 0.2};
  const double expected = brute_force(positions, triangles, p);
  positions = {}, triangles = {};
  EXPECT_EQ(tree.closest(p).squared_distance, expected);
}

TEST(TriangleTree, AnEmptyTreeAnswersTheLargestDistance) {
  const TriangleTree tree({}, {});
  EXPECT_EQ(tree.closest({1, 2, 3}).squared_distance, std::numeric_limits<double>::max());
}

}  // namespace
}  // namespace spheremap
