// T-junction cracks (core/prepare/t_junctions.h): a cube whose top is meshed with two
// vertices its neighbours' edges do not have, as CAD exports leave seams. Exact refuses
// it, repair zips the cracks (no vertex moves) and maps it certified.
#include <gtest/gtest.h>

#include <vector>

#include "core/map/pipeline.h"
#include "core/outputs/report_json.h"
#include "core/prepare/face_cleanup.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/t_junctions.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// The unit cube, outward. Corners 0-3 the bottom (z = 0), 4-7 the top, counter-clockwise
// seen from above; 8 and 9 the midpoints of the top's front edge (4-5) and back edge
// (7-6), lifted by `off` out of the cube. The top is two quads 4-8-9-7 and 8-5-6-9 (as
// 4 triangles, or 2 quads); every other face is 2 triangles (or 1 quad) that do not know
// of 8 and 9: two T-junctions.
PolygonMesh t_junction_cube(bool quads, double off = 0) {
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},      {0, 0, 1},
                    {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5, -off, 1}, {0.5, 1 + off, 1}};
  std::vector<std::vector<uint32_t>> faces = {
      {0, 3, 2, 1},   // bottom
      {0, 1, 5, 4},   // front (y = 0): its top edge 4-5 has 8 on it
      {1, 2, 6, 5},   // right
      {2, 3, 7, 6},   // back (y = 1): its top edge 6-7 has 9 on it
      {3, 0, 4, 7},   // left
      {4, 8, 9, 7},   // top, left half
      {8, 5, 6, 9}};  // top, right half
  for (const auto& face : faces) {
    if (quads) {
      mesh.add_face(face);
    } else {
      mesh.add_face(std::vector<uint32_t>{face[0], face[1], face[2]});
      mesh.add_face(std::vector<uint32_t>{face[0], face[2], face[3]});
    }
  }
  return mesh;
}

TEST(TJunctions, ExactRefusesTheCrackedCube) {
  PolygonMesh input = t_junction_cube(false);
  const PolygonMesh before = input;
  PrepareOptions options;
  options.method = PrepareMethod::kExact;
  const auto failures = input_failures(prepare_input(input, nullptr, options));
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "boundary");
  EXPECT_EQ(input.indices, before.indices);  // untouched
}

TEST(TJunctions, RepairZipsTheCracksAndMapsCertified) {
  for (const bool quads : {false, true}) {
    PolygonMesh input = t_junction_cube(quads);
    const size_t faces_before = input.face_count();
    PrepareOptions options;
    options.method = PrepareMethod::kRepair;
    const PreparedMesh prepared = prepare_input(input, nullptr, options);
    ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
    EXPECT_EQ(prepared.preparation.t_junctions_zipped, 2u);
    EXPECT_EQ(prepared.preparation.holes_filled, 0u);  // closed by the zip, not a fill
    // The two faces on the cracks each became one triangle more (a triangle: 2; a quad
    // fanned from a corner off the split edge: 3 instead of 1).
    EXPECT_EQ(input.face_count(), faces_before + (quads ? 4u : 2u));
    EXPECT_EQ(input.vertex_count(), 10u);  // no vertex added or moved
    EXPECT_EQ(input.positions[8], (Vec3{0.5, 0, 1}));
    const MappedMesh mapped = map_prepared(prepared, {});
    EXPECT_TRUE(mapped.map.check.bijective);
    EXPECT_EQ(metrics_json(mapped, {})["preparation"]["t_junctions_zipped"], 2);
  }
}

// The face ranges of a look follow the split faces (one source face, several faces).
TEST(TJunctions, CleanupKeepsFacesInPlace) {
  const PolygonMesh input = t_junction_cube(false);
  const FaceCleanup cleanup = clean_faces(input, 0);
  EXPECT_EQ(cleanup.t_junctions_zipped, 2u);
  EXPECT_EQ(cleanup.faces_split, 2u);
  ASSERT_EQ(cleanup.source_face.size(), input.face_count() + 2);
  for (size_t f = 1; f < cleanup.source_face.size(); ++f)
    EXPECT_LE(cleanup.source_face[f - 1], cleanup.source_face[f]);
  EXPECT_EQ(cleanup.flipped_faces, 0u);
}

// A vertex farther off the edge than kTJunctionTolerance of the diagonal is a real gap:
// nothing is zipped, and the mesh is refused as before.
TEST(TJunctions, LeavesAGapWiderThanTheTolerance) {
  PolygonMesh input = t_junction_cube(false, 1e-3);
  const FaceCleanup cleanup = clean_faces(input, 0);
  EXPECT_EQ(cleanup.t_junctions_zipped, 0u);
  PrepareOptions options;
  options.method = PrepareMethod::kRepair;
  options.max_hole_fill = 0;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.t_junctions_zipped, 0u);
  EXPECT_FALSE(input_failures(prepared).empty());
}

// Within the tolerance (1e-7 of the diagonal off the line) the crack is zipped.
TEST(TJunctions, ZipsAVertexSlightlyOffTheEdge) {
  const FaceCleanup cleanup = clean_faces(t_junction_cube(false, 1e-7), 0);
  EXPECT_EQ(cleanup.t_junctions_zipped, 2u);
}

// A hole's own boundary has no vertex on another boundary edge: nothing to zip; and an
// open sheet's boundary vertex lying on its own boundary's next edge is no crack either.
TEST(TJunctions, NothingToZipOnAnOrdinaryHole) {
  const PolygonMesh dome = testing::dome(2);
  EXPECT_TRUE(find_t_junctions(dome, dome.positions).empty());
  EXPECT_EQ(clean_faces(testing::without_face(testing::icosphere(2), 3), 0).t_junctions_zipped, 0u);
  // A triangle whose corner touches another triangle's edge: the pieces of that edge
  // would meet no other edge, so it stays whole (a touch, not a crack).
  PolygonMesh touch;
  touch.positions = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0.5, -1, 0}, {1.5, -1, 0}};
  touch.add_face(std::vector<uint32_t>{0, 1, 2});
  touch.add_face(std::vector<uint32_t>{3, 4, 5});
  EXPECT_TRUE(find_t_junctions(touch, touch.positions).empty());
}

}  // namespace
}  // namespace spheremap
