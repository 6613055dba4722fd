#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "core/mesh/triangle_tree.h"  // AxisBox
#include "core/mesh/union_find.h"
#include "core/mesh/weld.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// A cube stored as glTF stores it: 4 vertices per face, 24 in all.
PolygonMesh split_cube() {
  PolygonMesh welded = testing::quad_cube(1), split;
  for (size_t f = 0; f < welded.face_count(); ++f) {
    std::vector<uint32_t> corners;
    for (uint32_t v : welded.face(f)) {
      corners.push_back(static_cast<uint32_t>(split.positions.size()));
      split.positions.push_back(welded.positions[v]);
    }
    split.add_face(corners);
  }
  return split;
}

TEST(Weld, MergesExactDuplicatesAndKeepsTheMap) {
  const PolygonMesh split = split_cube();
  ASSERT_EQ(split.vertex_count(), 24u);
  const WeldResult r = weld(split);
  EXPECT_EQ(r.mesh.vertex_count(), 8u);
  ASSERT_EQ(r.input_to_welded.size(), 24u);
  for (size_t v = 0; v < 24; ++v)
    EXPECT_EQ(r.mesh.positions[r.input_to_welded[v]], split.positions[v]);
  for (size_t k = 0; k < split.indices.size(); ++k)
    EXPECT_EQ(r.mesh.indices[k], r.input_to_welded[split.indices[k]]);
}

TEST(Weld, KeepsOrderOfMeshWithoutDuplicates) {
  const PolygonMesh m = testing::icosphere(1);
  const WeldResult r = weld(m);
  EXPECT_EQ(r.mesh.positions, m.positions);
  EXPECT_EQ(r.mesh.indices, m.indices);
}

TEST(Weld, DropsUnreferencedVertices) {
  PolygonMesh m = testing::icosphere(0);
  m.positions.push_back({9, 9, 9});
  const WeldResult r = weld(m);
  EXPECT_EQ(r.unreferenced_vertices, 1u);
  EXPECT_EQ(r.mesh.vertex_count(), 12u);
  EXPECT_EQ(r.input_to_welded.back(), kUnreferenced);
}

TEST(Weld, ToleranceMergesNearbyPositionsOnly) {
  PolygonMesh m = split_cube();
  m.positions[5].x += 1e-9;
  EXPECT_EQ(weld(m).mesh.vertex_count(), 9u);        // exact: the nudged copy stays apart
  EXPECT_EQ(weld(m, 1e-6).mesh.vertex_count(), 8u);  // within 1e-6 x diagonal: merged
}

// Clusters of points a little apart (some chains of them longer than the tolerance, each
// link within it) welded at a tolerance: the groups are the connected components of
// "within tolerance x diagonal", as every pair compared says.
TEST(Weld, ToleranceGroupsAreTheComponentsOfNearPairs) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1), jitter(-1, 1);
  PolygonMesh m;
  for (int cluster = 0; cluster < 300; ++cluster) {
    Vec3 p{unit(random), unit(random), unit(random)};
    for (int k = 0; k < 4; ++k) {
      m.positions.push_back(p);
      p += Vec3{jitter(random), jitter(random), jitter(random)} * 0.004;
    }
  }
  m.positions.push_back({0, 0, 0}), m.positions.push_back({1, 1, 1});
  for (uint32_t v = 0; v + 2 < m.positions.size(); v += 3) m.add_face(std::array{v, v + 1, v + 2});
  m.add_face(std::array<uint32_t, 3>{0, uint32_t(m.positions.size() - 2),
                                     uint32_t(m.positions.size() - 1)});
  const double tolerance = 0.003;
  AxisBox box;
  for (const Vec3& p : m.positions) box.add(p);
  const double radius = tolerance * norm(box.hi - box.lo);
  UnionFind expected(m.positions.size());
  for (uint32_t a = 0; a < m.positions.size(); ++a)
    for (uint32_t b = 0; b < a; ++b)
      if (squared_norm(m.positions[a] - m.positions[b]) <= radius * radius) expected.unite(a, b);
  const WeldResult r = weld(m, tolerance);
  size_t merged = 0, apart = 0;
  for (uint32_t a = 0; a < m.positions.size(); ++a)
    for (uint32_t b = 0; b < a; ++b) {
      const bool together = expected.find(a) == expected.find(b);
      EXPECT_EQ(r.input_to_welded[a] == r.input_to_welded[b], together) << a << " " << b;
      (together ? merged : apart) += 1;
    }
  EXPECT_GT(merged, 100u);  // the test has both kinds of pairs
  EXPECT_GT(apart, 100u);
}

// A tolerance whose grid would have more cells across the mesh than an int64_t counts is
// refused by name; the cells count from the mesh's corner, so far from the origin is fine.
TEST(Weld, ATinyToleranceIsRefusedAndAFarMeshWeldsAsNearTheOrigin) {
  PolygonMesh m = testing::icosphere(1);
  EXPECT_THROW(weld(m, 1e-300), InputError);
  m.positions.push_back(m.positions[0] + Vec3{1e-7, 0, 0});  // a copy of vertex 0, nudged
  m.add_face(std::array<uint32_t, 3>{uint32_t(m.positions.size() - 1), 1, 2});
  const size_t near_origin = weld(m, 1e-6).mesh.vertex_count();
  for (Vec3& p : m.positions) p += Vec3{3e5, -2e5, 1e5};  // the nudge still 1e-7 there
  EXPECT_EQ(weld(m, 1e-6).mesh.vertex_count(), near_origin);
  EXPECT_EQ(near_origin, m.positions.size() - 1);
}

TEST(Weld, NeverMergesNonFinitePositions) {
  PolygonMesh m = split_cube();
  m.positions[0] = {NAN, 0, 0};
  m.positions[1] = {NAN, 0, 0};
  const WeldResult r = weld(m);
  EXPECT_NE(r.input_to_welded[0], r.input_to_welded[1]);
}

}  // namespace
}  // namespace spheremap
