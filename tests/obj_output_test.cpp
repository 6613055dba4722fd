// OBJ output of polygons: a reader that fans each polygon from its first corner (three.js,
// Blender, most loaders) must get the triangulation the map was certified on.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <vector>

#include "core/io/obj.h"
#include "core/io/text_reader.h"
#include "core/mesh/mesh.h"
#include "tests/corpus.h"

namespace spheremap {
namespace {

using TriangleSet = std::set<std::array<uint32_t, 3>>;

// A triangle up to rotation of its corners (orientation kept).
std::array<uint32_t, 3> rotated_to_smallest(uint32_t a, uint32_t b, uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

// What a loader does: each polygon fanned from its first corner, independently of our
// fan_triangulate.
TriangleSet first_corner_fans(const PolygonMesh& mesh) {
  TriangleSet out;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 1; k + 1 < face.size(); ++k)
      out.insert(rotated_to_smallest(face[0], face[k], face[k + 1]));
  }
  return out;
}

TriangleSet certified_triangles(const PolygonMesh& mesh) {
  TriangleSet out;
  for (const Triangle& t : fan_triangulate(mesh).triangles)
    out.insert(rotated_to_smallest(t[0], t[1], t[2]));
  return out;
}

// A closed "pillow": the quad 0-1-2-3 and, behind it, the triangles 0-2-1 and 0-3-2, so
// the quad's diagonal 0-2 is already an edge and it must be split along 1-3 (apex 1):
// a fan from its first corner would make edge 0-2 shared by four triangles.
PolygonMesh pillow() {
  PolygonMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0.1}, {1, 1, 0}, {0, 1, 0.1}};
  const uint32_t quad[] = {0, 1, 2, 3}, back1[] = {0, 2, 1}, back2[] = {0, 3, 2};
  m.add_face(quad);
  m.add_face(back1);
  m.add_face(back2);
  return m;
}

TEST(ObjOutput, PolygonsStartAtTheirFanApex) {
  const PolygonMesh mesh = pillow();
  // The case matters: the loader's fan of the input as given differs from ours.
  ASSERT_NE(first_corner_fans(mesh), certified_triangles(mesh));
  const PolygonMesh written = parse_obj(format_obj(mesh));
  EXPECT_EQ(first_corner_fans(written), certified_triangles(mesh));
  EXPECT_EQ(certified_triangles(written), certified_triangles(mesh));  // same map input
  EXPECT_EQ(written.positions.size(), mesh.positions.size());
  EXPECT_EQ(written.face_count(), mesh.face_count());
}

TEST(ObjOutput, ApexFirstKeepsTheTriangulationOfARealQuadMesh) {
  SKIP_WITHOUT_CORPUS("beast.obj");
  const PolygonMesh mesh = parse_obj(read_file(testing::corpus_path("beast.obj")));
  const PolygonMesh written = parse_obj(format_obj(mesh));
  EXPECT_EQ(first_corner_fans(written), certified_triangles(mesh));
}

}  // namespace
}  // namespace spheremap
