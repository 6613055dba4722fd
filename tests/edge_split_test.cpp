// Splitting non-manifold edges where closed surfaces meet (core/prepare/edge_split.h): a
// tetrahedron welded into a cube's corner (3 edges of 4 faces) becomes two closed parts
// that map exactly under auto, instead of one envelope that loses the tetrahedron's inner
// face; a fin (an edge of 3 faces) is left as it was.
#include <gtest/gtest.h>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/report_json.h"
#include "core/prepare/edge_split.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(EdgeSplit, SharesOutEdgesBetweenClosedSurfaces) {
  PolygonMesh mesh = weld(testing::cube_and_corner_tetrahedron(), 0).mesh;
  ASSERT_EQ(analyze_topology(mesh).non_manifold_edges, 3u);
  const size_t vertices = mesh.vertex_count();
  const EdgeSplit split = split_non_manifold_edges(mesh);
  EXPECT_EQ(split.edges_split, 3u);
  EXPECT_EQ(split.vertices_added, 4u);  // the tetrahedron's corners, each once
  EXPECT_EQ(mesh.vertex_count(), vertices + 4);
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_EQ(topology.component_vertices.size(), 2u);
}

TEST(EdgeSplit, LeavesAFinAndAManifoldMeshAsTheyAre) {
  PolygonMesh finned = weld(testing::cube_and_corner_tetrahedron(true), 0).mesh;
  ASSERT_EQ(analyze_topology(finned).non_manifold_edges, 4u);
  const PolygonMesh before = finned;
  // The fin's edge cannot be shared out, so the cube and the fin stay one sheet; the
  // tetrahedron's three edges still split off.
  EXPECT_EQ(split_non_manifold_edges(finned).edges_split, 3u);
  EXPECT_EQ(analyze_topology(finned).non_manifold_edges, 1u);
  PolygonMesh sphere = testing::icosphere(2);
  const PolygonMesh round = sphere;
  EXPECT_EQ(split_non_manifold_edges(sphere).edges_split, 0u);
  EXPECT_EQ(sphere.indices, round.indices);
  EXPECT_EQ(sphere.positions, round.positions);
}

TEST(EdgeSplit, AutoMapsTheSolidInsideAsAPartInsteadOfWrappingIt) {
  PolygonMesh input = testing::cube_and_corner_tetrahedron();
  PrepareOptions options;
  options.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.decided, "parts");
  EXPECT_EQ(prepared.preparation.edges_split, 3u);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  ASSERT_EQ(prepared.parts.size(), 2u);
  EXPECT_TRUE(prepared.parts[0].mappable() && prepared.parts[1].mappable());
  EXPECT_EQ(prepared.welded.mesh.face_count(), 16u);  // every input face kept
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_EQ(mapped.parts.size(), 2u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);

  PolygonMesh again = testing::cube_and_corner_tetrahedron();
  PrepareOptions exact;
  exact.method = PrepareMethod::kExact;
  EXPECT_EQ(input_failures(prepare_input(again, nullptr, exact)).front().check,
            "non_manifold_edge");
}

}  // namespace
}  // namespace spheremap
