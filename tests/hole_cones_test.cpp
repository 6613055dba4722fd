// Parts with holes and handles (core/prepare/hole_cones.h): a torus with a patch taken out
// is neither closed (for handle_closing.h) nor an open sphere (for open_part_cuts.h), so
// prepare=auto wrapped it. Its hole is coned for the handle search, the handle cut and left
// open, the cone taken out: the part maps as a disc closed by its own back, every input
// face kept and no point moved.
#include <gtest/gtest.h>

#include <vector>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/report_json.h"
#include "core/prepare/hole_cones.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(HoleCones, OnlyPartsWithHandlesAreConed) {
  // A dome (open, genus 0), a holed torus (open, genus 1), a sphere (closed), a Moebius band
  // (not orientable).
  const PolygonMesh kit = testing::assembled({{testing::dome(2), {0, 0, 0}},
                                              {testing::holed_torus(24, 12), {6, 0, 0}},
                                              {testing::icosphere(1), {12, 0, 0}},
                                              {testing::moebius_band(24), {18, 0, 0}}});
  PolygonMesh mesh = kit;
  const TopologyReport before = analyze_topology(mesh);
  const HoleCones cones = cone_holes_of_parts_with_handles(mesh);
  EXPECT_EQ(cones.parts, 1u);
  EXPECT_EQ(cones.loops, 1u);
  EXPECT_EQ(cones.first_face, kit.face_count());
  EXPECT_EQ(mesh.face_count(), kit.face_count() + cones.faces);
  EXPECT_EQ(mesh.vertex_count(), kit.vertex_count() + 1);  // one apex
  // The torus's hole (a 6 x 3 patch of quads: 18 edges round) is closed, the others not.
  EXPECT_EQ(cones.faces, 18u);
  const TopologyReport after = analyze_topology(mesh);
  EXPECT_EQ(after.boundary_edges, before.boundary_edges - 18);
  EXPECT_EQ(after.non_manifold_edges + after.non_manifold_vertices, 0u);
  for (size_t k = 0; k < kit.indices.size(); ++k) EXPECT_EQ(mesh.indices[k], kit.indices[k]);
}

TEST(HoleCones, AutoMapsATorusWithAHoleAsItsDoubledDiscNotAnEnvelope) {
  PolygonMesh input = testing::holed_torus(24, 12);
  const size_t input_faces = input.face_count();
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  EXPECT_EQ(prepared.preparation.decided, "repair");
  EXPECT_EQ(prepared.preparation.handles_opened + prepared.preparation.handles_closed, 1u);
  EXPECT_EQ(prepared.preparation.sheets_doubled, 1u);
  EXPECT_EQ(input.face_count(), input_faces);  // the input's own faces, not an envelope's
  // The cone is gone: every welded vertex lies on the input's faces (the back's midpoints
  // and centroids too); the apex, at the hole's centroid, stood 0.2 off the torus.
  const TriangleTree surface = polygon_tree(input, [&] {
    std::vector<uint32_t> faces(input.face_count());
    for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
    return faces;
  }());
  for (const Vec3& p : prepared.welded.mesh.positions)
    EXPECT_LT(surface.squared_distance(p), 1e-20) << p.x << " " << p.y << " " << p.z;
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);

  // Without backs (double_open_sheets off), nothing is coned and the torus is wrapped.
  PolygonMesh again = testing::holed_torus(24, 12);
  automatic.double_open_sheets = false;
  automatic.envelope.resolution = 96;
  EXPECT_EQ(prepare_input(again, nullptr, automatic).preparation.decided, "wrap");
}

// The same torus with fills allowed up to its whole area: the hole's fill, a flat cap
// across a curved patch, would stand over 1% of the torus's diagonal off it, so the hole is
// left for the back as an open sphere's far hole is (far_hole_fills.h), not capped with the
// handle closed around it.
TEST(HoleCones, AFarHoleOfAPartWithHandlesIsLeftForItsBack) {
  PolygonMesh input = testing::holed_torus(24, 12);
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  automatic.max_hole_fill = 1;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  EXPECT_EQ(prepared.preparation.holes_filled, 0u);
  EXPECT_EQ(prepared.preparation.sheets_doubled, 1u);
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  std::vector<uint32_t> faces(input.face_count());
  for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
  const TriangleTree surface = polygon_tree(input, faces);
  for (const Vec3& p : prepared.welded.mesh.positions)  // no cap: all on the input's faces
    EXPECT_LT(surface.squared_distance(p), 1e-20) << p.x << " " << p.y << " " << p.z;
}

}  // namespace
}  // namespace spheremap
