// Handles opened instead of capped (core/prepare/handle_opening.h): under prepare=auto a
// part whose nearest caps stand far from it (a torus: the cap spans its inner hole) keeps
// its cuts open, is cut into a disc and closed by its back, so its remesh stays on the
// surface; a part whose cap lies near keeps the cap; the other methods still cap.
#include <gtest/gtest.h>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/handle_closing.h"
#include "core/prepare/handle_opening.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

PrepareOptions with(PrepareMethod method) {
  PrepareOptions options;
  options.method = method;
  return options;
}

double remesh_distance(const PreparedMesh& prepared) {
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  return remesh_asset(mapped, 128, 1).metrics["distance"]["hausdorff"].get<double>();
}

TEST(HandleOpening, TakesOutFarCapsAndLeavesTheCutsOpen) {
  PolygonMesh mesh = weld(testing::torus(12, 24), 0).mesh;
  const size_t vertices = mesh.vertex_count(), faces = mesh.face_count();
  const HandleClosing closed = close_handles(mesh, 1.5);
  ASSERT_EQ(closed.handles_closed, 1u);
  ASSERT_EQ(closed.closed_parts.size(), 1u);
  EXPECT_GT(closed.farthest_fill, 0.05);  // the cap spans the tube's width at least
  const HandleOpening opened = open_far_handles(mesh, closed, 0.01);
  EXPECT_EQ(opened.parts_opened, 1u);
  EXPECT_EQ(opened.handles_opened, 1u);
  EXPECT_EQ(opened.faces_removed, closed.faces_added);
  EXPECT_EQ(opened.farthest_fill, 0);
  EXPECT_EQ(mesh.face_count(), faces);  // the torus's own faces, its cut's copies in place
  EXPECT_EQ(mesh.vertex_count(), vertices + closed.copy_of.size());
  const TopologyReport cut = analyze_topology(mesh);
  EXPECT_EQ(cut.boundary_loops, 2u);
  EXPECT_EQ(cut.euler_characteristic, 0);  // an open cylinder
  EXPECT_EQ(cut.non_manifold_vertices + cut.non_manifold_edges, 0u);

  // A cap within `near` stays.
  PolygonMesh again = weld(testing::torus(12, 24), 0).mesh;
  const HandleClosing capped = close_handles(again, 1.5);
  const HandleOpening kept = open_far_handles(again, capped, 1.0);
  EXPECT_EQ(kept.handles_opened, 0u);
  EXPECT_EQ(kept.farthest_fill, capped.farthest_fill);
  EXPECT_EQ(again.face_count(), faces + capped.faces_added);
}

// Under auto a torus maps exactly (no cap), its remesh within 2% of it where the capped
// one's is far; repair still caps it.
TEST(HandleOpening, AutoMapsATorusByItsCutsAndBackWhereACapWouldStandFar) {
  PolygonMesh input = testing::torus(12, 24);
  const size_t input_faces = input.face_count();
  const PreparedMesh prepared = prepare_input(input, nullptr, with(PrepareMethod::kAuto));
  EXPECT_EQ(prepared.preparation.decided, "repair");
  EXPECT_EQ(prepared.preparation.handles_closed, 0u);
  EXPECT_EQ(prepared.preparation.handles_opened, 1u);
  EXPECT_EQ(prepared.preparation.farthest_handle_fill, 0);
  EXPECT_EQ(prepared.preparation.open_parts_cut, 1u);
  EXPECT_EQ(prepared.preparation.sheets_doubled, 1u);
  EXPECT_TRUE(prepared.filled.empty());
  EXPECT_LT(remesh_distance(prepared), 0.02);
  const MappedMesh mapped = map_prepared(prepared, {});
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(sphere.written.triangles, 2 * input_faces);  // quads, two triangles each
  EXPECT_EQ(sphere.metrics["preparation"]["handles_opened"], 1);

  PolygonMesh capped_input = testing::torus(12, 24);
  const PreparedMesh capped = prepare_input(capped_input, nullptr, with(PrepareMethod::kRepair));
  EXPECT_EQ(capped.preparation.handles_closed, 1u);
  EXPECT_EQ(capped.preparation.handles_opened, 0u);
  EXPECT_GT(remesh_distance(capped), 0.04);
}

// Three through-holes in a plate (genus 3) whose caps stand far: six loops joined into one
// disc. A thin plate's hole, whose cap through the wall lies near, keeps its cap.
TEST(HandleOpening, OpensEveryFarHandleOfAPartAndKeepsANearCap) {
  PolygonMesh plate = testing::plate_with_holes(7, 3, {{1, 1}, {3, 1}, {5, 1}});
  const PreparedMesh opened = prepare_input(plate, nullptr, with(PrepareMethod::kAuto));
  EXPECT_EQ(opened.preparation.handles_opened, 3u);
  EXPECT_EQ(opened.preparation.handles_closed, 0u);
  EXPECT_LT(remesh_distance(opened), 0.02);

  PolygonMesh thin = testing::plate_with_holes(7, 7, {{3, 3}}, 0.1);
  const PreparedMesh near = prepare_input(thin, nullptr, with(PrepareMethod::kAuto));
  EXPECT_EQ(near.preparation.handles_closed, 1u);
  EXPECT_EQ(near.preparation.handles_opened, 0u);
  EXPECT_GT(near.preparation.farthest_handle_fill, 0);
  EXPECT_LE(near.preparation.farthest_handle_fill, 0.01);
}

}  // namespace
}  // namespace spheremap
