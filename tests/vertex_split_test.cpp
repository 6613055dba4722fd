// Splitting non-manifold vertices (core/prepare/vertex_split.h): one vertex per fan, on the
// welded mesh, with the input's vertices following; two solids touching at a point become
// two parts that map, a surface pinched to a point maps as the sphere it is; exact still
// refuses.
#include <gtest/gtest.h>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/vertex_split.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(VertexSplit, GivesEachFanItsOwnVertex) {
  PolygonMesh mesh = testing::pinched_tetrahedra();
  ASSERT_EQ(analyze_topology(mesh).non_manifold_vertices, 1u);
  const size_t vertices = mesh.vertex_count();
  const VertexSplit split = split_non_manifold_vertices(mesh);
  EXPECT_EQ(split.vertices_split, 1u);
  EXPECT_EQ(split.vertices_added, 1u);
  ASSERT_EQ(mesh.vertex_count(), vertices + 1);
  EXPECT_EQ(mesh.positions.back(), mesh.positions[0]);
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_vertices, 0u);
  EXPECT_EQ(topology.component_vertices.size(), 2u);
  // A manifold mesh is untouched.
  PolygonMesh sphere = testing::icosphere(2);
  const PolygonMesh before = sphere;
  EXPECT_EQ(split_non_manifold_vertices(sphere).vertices_split, 0u);
  EXPECT_EQ(sphere.indices, before.indices);
  EXPECT_EQ(sphere.positions, before.positions);
}

TEST(VertexSplit, TwoSolidsTouchingAtAPointMapAsTwoParts) {
  PolygonMesh input = testing::pinched_tetrahedra();
  const size_t input_vertices = input.vertex_count();
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  EXPECT_EQ(prepared.preparation.vertices_split, 1u);
  EXPECT_EQ(input.vertex_count(), input_vertices + 1);  // the shared input vertex copied
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_EQ(mapped.parts.size(), 2u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(sphere.metrics["preparation"]["non_manifold_vertices_split"], 1);

  PolygonMesh again = testing::pinched_tetrahedra();
  PrepareOptions exact;
  exact.method = PrepareMethod::kExact;
  EXPECT_EQ(input_failures(prepare_input(again, nullptr, exact)).front().check,
            "non_manifold_vertex");
}

TEST(VertexSplit, ASurfacePinchedToAPointMapsAsItsSphere) {
  // Two far vertices of a sphere at one point: welded, a vertex of two fans (genus 1 by
  // the count, but a sphere once split). The input keeps its two vertices: each moves
  // with its own fan, no copy is needed.
  PolygonMesh input = testing::icosphere(2);
  uint32_t far = 0;
  for (uint32_t v = 1; v < input.vertex_count(); ++v)
    if (dot(input.positions[v], input.positions[0]) < dot(input.positions[far], input.positions[0]))
      far = v;
  input.positions[far] = input.positions[0];
  const size_t input_vertices = input.vertex_count();
  PrepareOptions repair;
  repair.method = PrepareMethod::kRepair;
  const PreparedMesh prepared = prepare_input(input, nullptr, repair);
  EXPECT_EQ(prepared.preparation.vertices_split, 1u);
  EXPECT_EQ(prepared.preparation.handles_closed, 0u);
  EXPECT_EQ(input.vertex_count(), input_vertices);
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_TRUE(sphere.metrics["bijective_as_written"]);
}

}  // namespace
}  // namespace spheremap
