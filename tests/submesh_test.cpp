// submesh: some faces of a mesh as a mesh of their own, vertices in first-use order.
#include <gtest/gtest.h>

#include "core/mesh/submesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// Five vertices at x = 0..4; a triangle, a triangle and a quad.
PolygonMesh five_vertices() {
  PolygonMesh mesh;
  for (int v = 0; v < 5; ++v) mesh.positions.push_back({double(v), 0, 0});
  mesh.add_face(std::vector<uint32_t>{0, 1, 2});
  mesh.add_face(std::vector<uint32_t>{2, 3, 4});
  mesh.add_face(std::vector<uint32_t>{4, 3, 1, 0});
  return mesh;
}

TEST(Submesh, FacesInTheGivenOrderVerticesInFirstUseOrder) {
  const PolygonMesh mesh = five_vertices();
  const std::vector<uint32_t> faces{2, 0};
  const MeshPart part = submesh(mesh, faces);
  EXPECT_EQ(part.vertex, (std::vector<uint32_t>{4, 3, 1, 0, 2}));
  ASSERT_EQ(part.mesh.vertex_count(), 5u);
  for (size_t v = 0; v < 5; ++v) EXPECT_EQ(part.mesh.positions[v].x, double(part.vertex[v]));
  ASSERT_EQ(part.mesh.face_count(), 2u);
  EXPECT_EQ(std::vector<uint32_t>(part.mesh.face(0).begin(), part.mesh.face(0).end()),
            (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(std::vector<uint32_t>(part.mesh.face(1).begin(), part.mesh.face(1).end()),
            (std::vector<uint32_t>{3, 2, 4}));
}

TEST(Submesh, UnusedVerticesAreDropped) {
  const PolygonMesh mesh = five_vertices();
  const std::vector<uint32_t> faces{1};
  const MeshPart part = submesh(mesh, faces);
  EXPECT_EQ(part.vertex, (std::vector<uint32_t>{2, 3, 4}));
  ASSERT_EQ(part.mesh.face_count(), 1u);
  EXPECT_EQ(part.mesh.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(Submesh, EmptyListGivesAnEmptyMesh) {
  const MeshPart part = submesh(five_vertices(), {});
  EXPECT_EQ(part.mesh.vertex_count(), 0u);
  EXPECT_EQ(part.mesh.face_count(), 0u);
  EXPECT_EQ(part.mesh.offsets, (std::vector<uint32_t>{0}));
  EXPECT_TRUE(part.vertex.empty());
}

TEST(Submesh, ScratchIsLeftUnusedAndGivesTheSameMesh) {
  const PolygonMesh mesh = testing::icosphere(1);
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < mesh.face_count(); f += 3) faces.push_back(f);
  std::vector<uint32_t> scratch(mesh.vertex_count(), kUnreferenced);
  const MeshPart with = submesh(mesh, faces, &scratch);
  const MeshPart without = submesh(mesh, faces);
  EXPECT_EQ(with.vertex, without.vertex);
  EXPECT_EQ(with.mesh.indices, without.mesh.indices);
  EXPECT_EQ(with.mesh.offsets, without.mesh.offsets);
  for (uint32_t id : scratch) EXPECT_EQ(id, kUnreferenced);
  // Every face kept, corners naming the same old vertices.
  ASSERT_EQ(with.mesh.face_count(), faces.size());
  for (size_t k = 0; k < faces.size(); ++k)
    for (size_t c = 0; c < 3; ++c)
      EXPECT_EQ(with.vertex[with.mesh.face(k)[c]], mesh.face(faces[k])[c]);
}

TEST(KeptTriangles, KeepsTheUnmarkedInTheirOrderOrAllWhenNothingIsMarked) {
  const std::vector<Triangle> triangles = {{0, 1, 2}, {2, 1, 3}, {3, 4, 5}, {5, 4, 0}};
  const std::vector<char> left_out = {0, 1, 0, 1};
  EXPECT_EQ(kept_triangles(triangles, left_out), (std::vector<Triangle>{{0, 1, 2}, {3, 4, 5}}));
  EXPECT_EQ(kept_triangles(triangles, {}), triangles);
  EXPECT_TRUE(kept_triangles(triangles, std::vector<char>(4, 1)).empty());
}

}  // namespace
}  // namespace spheremap
