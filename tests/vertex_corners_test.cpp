// VertexCorners (core/prepare/vertex_corners.h): the flat corner index handle closing walks
// answers every half-edge as corner_map's hash map does, refuses the same meshes, and finds
// corners of a vertex with thousands of them.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "core/prepare/corner_map.h"
#include "core/prepare/hole_filling.h"
#include "core/prepare/vertex_corners.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

std::vector<uint32_t> every_face(const PolygonMesh& mesh) {
  std::vector<uint32_t> faces(mesh.face_count());
  std::iota(faces.begin(), faces.end(), 0u);
  return faces;
}

// Every corner of `faces` found under its half-edge, with its slot, face position and the
// vertices around it, as corner_map gives them; and no half-edge the faces lack.
void expect_same_as_corner_map(const PolygonMesh& mesh, const std::vector<uint32_t>& faces) {
  const auto index = VertexCorners::of_faces(mesh, faces);
  const auto map = corner_map(mesh, faces);
  ASSERT_TRUE(index && map);
  EXPECT_EQ(index->corners(), map->size());
  size_t used = 0;
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) used += !index->at(v).empty();
  EXPECT_EQ(index->vertices(), used);
  for (uint32_t position = 0; position < faces.size(); ++position) {
    const auto face = mesh.face(faces[position]);
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      const VertexCorner* corner = index->find(a, b);
      ASSERT_NE(corner, nullptr);
      EXPECT_EQ(corner->slot, map->at(directed_edge_key(a, b)));
      EXPECT_EQ(corner->face, position);
      EXPECT_EQ(corner->next, b);
      EXPECT_EQ(corner->prev, face[(k + face.size() - 1) % face.size()]);
      EXPECT_EQ(index->find(b, a) != nullptr, map->count(directed_edge_key(b, a)) == 1);
    }
  }
}

TEST(VertexCorners, AnswersEveryHalfEdgeAsTheCornerMapDoes) {
  expect_same_as_corner_map(testing::torus(24, 12), every_face(testing::torus(24, 12)));
  expect_same_as_corner_map(testing::quad_cube(5), every_face(testing::quad_cube(5)));
  // A subset of faces (an open patch: half-edges on its rim have no twin), in another order.
  const PolygonMesh sphere = testing::icosphere(3);
  std::vector<uint32_t> some;
  for (uint32_t f = static_cast<uint32_t>(sphere.face_count()); f-- > 0;)
    if (f % 3 != 0) some.push_back(f);
  expect_same_as_corner_map(sphere, some);
}

TEST(VertexCorners, RefusesWhatTheCornerMapRefuses) {
  // Two faces running the same way along an edge.
  PolygonMesh flipped = testing::icosphere(1);
  const std::vector<uint32_t> face(flipped.face(0).begin(), flipped.face(0).end());
  flipped.add_face(std::vector<uint32_t>{face[0], face[1], face[2]});
  EXPECT_FALSE(corner_map(flipped, every_face(flipped)));
  EXPECT_FALSE(VertexCorners::of_faces(flipped, every_face(flipped)));
  // A face repeating a vertex in a row.
  PolygonMesh repeated = testing::icosphere(1);
  repeated.add_face(std::vector<uint32_t>{0, 0, 1});
  EXPECT_FALSE(corner_map(repeated, every_face(repeated)));
  EXPECT_FALSE(VertexCorners::of_faces(repeated, every_face(repeated)));
}

// A cone of 20,000 faces around one apex: each of its corners found (by bisection: a scan
// per query would be quadratic).
TEST(VertexCorners, FindsEachCornerOfAVertexWithThousands) {
  constexpr uint32_t kRim = 20000;
  PolygonMesh cone;
  for (uint32_t k = 0; k < kRim; ++k)
    cone.positions.push_back({std::cos(k * 2e-4), std::sin(k * 2e-4), 0});
  cone.positions.push_back({0, 0, 1});
  for (uint32_t k = 0; k < kRim; ++k) cone.add_face(std::vector<uint32_t>{kRim, k, (k + 1) % kRim});
  const auto index = VertexCorners::of_faces(cone, every_face(cone));
  ASSERT_TRUE(index);
  EXPECT_EQ(index->at(kRim).size(), kRim);
  for (uint32_t k = 0; k < kRim; ++k) {
    const VertexCorner* corner = index->find(kRim, k);
    ASSERT_NE(corner, nullptr);
    EXPECT_EQ(corner->face, k);
    EXPECT_EQ(corner->prev, (k + 1) % kRim);
  }
  EXPECT_EQ(index->find(kRim, kRim), nullptr);
}

}  // namespace
}  // namespace spheremap
