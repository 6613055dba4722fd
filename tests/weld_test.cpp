#include <gtest/gtest.h>

#include <cmath>

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

TEST(Weld, NeverMergesNonFinitePositions) {
  PolygonMesh m = split_cube();
  m.positions[0] = {NAN, 0, 0};
  m.positions[1] = {NAN, 0, 0};
  const WeldResult r = weld(m);
  EXPECT_NE(r.input_to_welded[0], r.input_to_welded[1]);
}

}  // namespace
}  // namespace spheremap
