#include "core/mesh/half_edge_ends.h"

#include <gtest/gtest.h>

#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(HalfEdgeEnds, CountsEachDirectionAndTheFacesBesideAnEdge) {
  PolygonMesh mesh;  // faces alone, no positions: two triangles on edge 1-2, one reversed
  mesh.add_face(std::vector<uint32_t>{0, 1, 2});
  mesh.add_face(std::vector<uint32_t>{2, 1, 3});
  mesh.add_face(std::vector<uint32_t>{1, 2, 4});  // 1 -> 2 a second time: a fin
  const HalfEdgeEnds ends(mesh);
  EXPECT_EQ(ends.count(1, 2), 2u);
  EXPECT_EQ(ends.count(2, 1), 1u);
  EXPECT_EQ(ends.faces_beside(1, 2), 3u);
  EXPECT_EQ(ends.faces_beside(0, 1), 1u);
  EXPECT_FALSE(ends.has(1, 0));
  EXPECT_FALSE(ends.has(7, 0));  // a vertex no face uses
}

TEST(HalfEdgeEnds, EveryEdgeOfAClosedSphereHasItsReverseAndOneHoleLeavesThreeWithout) {
  const PolygonMesh sphere = testing::icosphere(2);
  const PolygonMesh open = testing::without_face(sphere, 5);
  for (const PolygonMesh* mesh : {&sphere, &open}) {
    const HalfEdgeEnds ends(*mesh);
    size_t without_reverse = 0;
    for (size_t f = 0; f < mesh->face_count(); ++f) {
      const auto face = mesh->face(f);
      for (size_t k = 0; k < face.size(); ++k)
        without_reverse += !ends.has(face[(k + 1) % face.size()], face[k]);
    }
    EXPECT_EQ(without_reverse, mesh == &sphere ? 0u : 3u);
  }
}

}  // namespace
}  // namespace spheremap
