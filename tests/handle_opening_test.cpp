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

// Two open tubes touching at one vertex, with a cap (appended after their faces, as
// close_handles appends its fills) standing far from them: without the cap they are one
// piece only through that vertex, and once it is split per fan two open spheres, each of
// which becomes a disc. The cap is taken out (it was kept when the piece had to be one
// open sphere).
TEST(HandleOpening, OpensAPartThatFallsIntoOpenSpheresAtATouchingCut) {
  PolygonMesh mesh;
  const int around = 6;
  // Tube k: rings at z = 0 and 1 around (2k, 0); tube 1's vertex at angle pi is tube 0's
  // vertex at angle 0, (1, 0, 0).
  std::vector<std::vector<uint32_t>> ring(4);
  for (int k = 0; k < 2; ++k)
    for (int z = 0; z < 2; ++z)
      for (int a = 0; a < around; ++a) {
        const double angle = 2 * M_PI * a / around + (k ? M_PI : 0);
        if (k == 1 && z == 0 && a == 0) {
          ring[2 + z].push_back(ring[0][0]);
          continue;
        }
        ring[2 * k + z].push_back(static_cast<uint32_t>(mesh.positions.size()));
        mesh.positions.push_back({2.0 * k + std::cos(angle), std::sin(angle), double(z)});
      }
  for (int k = 0; k < 2; ++k)
    for (int a = 0; a < around; ++a) {
      const int b = (a + 1) % around;
      const uint32_t quad[4] = {ring[2 * k][a], ring[2 * k][b], ring[2 * k + 1][b],
                                ring[2 * k + 1][a]};
      mesh.add_face(quad);
    }
  const size_t tube_faces = mesh.face_count();
  const uint32_t centre = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back({0, 0, 1.5});
  for (int a = 0; a < around; ++a) {  // the cap over tube 0's top, a cone standing off it
    const uint32_t fan[3] = {ring[1][(a + 1) % around], ring[1][a], centre};
    mesh.add_face(fan);
  }
  ASSERT_EQ(analyze_topology(mesh).non_manifold_vertices, 1u);
  HandleClosing closed;
  closed.closed_parts.push_back({tube_faces, static_cast<size_t>(around), 1, 0.3, false});
  const HandleOpening opened = open_far_handles(mesh, closed, 0.01);
  EXPECT_EQ(opened.parts_opened, 1u);
  EXPECT_EQ(opened.handles_opened, 1u);
  EXPECT_EQ(opened.faces_removed, static_cast<size_t>(around));
  EXPECT_EQ(opened.farthest_fill, 0);
  EXPECT_EQ(opened.vertices_split, 1u);
  EXPECT_EQ(mesh.face_count(), tube_faces);
  const TopologyReport tubes = analyze_topology(mesh);
  EXPECT_EQ(tubes.non_manifold_vertices, 0u);
  EXPECT_EQ(tubes.component_faces.size(), 2u);
  EXPECT_EQ(tubes.boundary_loops, 4u);
}

}  // namespace
}  // namespace spheremap
