// Sheets that end on a surface (core/prepare/sheet_ends.h): a fin on a closed cube's edge
// and a room's walls standing on its floor. Each such edge has two faces of the surface
// passing through and one of the sheet ending there; the ending sheet lets go (gets a
// boundary), so the cube maps as it is and the floor and walls as doubled sheets, where
// before the whole was one non-manifold part, wrapped.
#include <gtest/gtest.h>

#include <array>
#include <map>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/report_json.h"
#include "core/prepare/edge_split.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/sheet_ends.h"
#include "core/prepare/vertex_split.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// A floor of n x n unit quads (one-sided, facing up) and two walls of `height` standing
// on it along x = 2 and y = 3 (one-sided quads whose lower edges are the floor's edges),
// crossing nowhere: the L of a room's inner walls. Vertices shared by position.
PolygonMesh floor_and_walls(int n, double height) {
  PolygonMesh mesh;
  std::map<std::array<double, 3>, uint32_t> id;
  auto at = [&](double x, double y, double z) {
    const auto [it, added] = id.emplace(std::array{x, y, z}, uint32_t(mesh.positions.size()));
    if (added) mesh.positions.push_back({x, y, z});
    return it->second;
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      mesh.add_face(std::array{at(x, y, 0), at(x + 1, y, 0), at(x + 1, y + 1, 0), at(x, y + 1, 0)});
  for (int y = 0; y < 3; ++y)  // x = 2, from y = 0 to 3
    mesh.add_face(std::array{at(2, y, 0), at(2, y + 1, 0), at(2, y + 1, height), at(2, y, height)});
  for (int x = 3; x < n; ++x)  // y = 3, from x = 3 to n
    mesh.add_face(std::array{at(x, 3, 0), at(x + 1, 3, 0), at(x + 1, 3, height), at(x, 3, height)});
  return mesh;
}

TEST(SheetEnds, AFinLetsGoOfTheCubeItStandsOn) {
  PolygonMesh mesh = weld(testing::cube_and_corner_tetrahedron(true), 0).mesh;
  split_non_manifold_edges(mesh);  // the tetrahedron's edges; the fin's is left
  ASSERT_EQ(analyze_topology(mesh).non_manifold_edges, 1u);
  const size_t boundary = analyze_topology(mesh).boundary_edges;
  const EdgePairs pairs = pair_sheets_ending_on_edges(mesh);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs.begin()->second.size(), 2u);  // the cube's two faces, with each other
  const PolygonMesh before = mesh;
  EXPECT_EQ(split_non_manifold_vertices(mesh, nullptr, &pairs).vertices_added, 2u);
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_edges + topology.non_manifold_vertices, 0u);
  EXPECT_EQ(topology.boundary_edges, boundary + 1);   // the fin's foot
  for (size_t k = 0; k < before.indices.size(); ++k)  // nothing moved
    EXPECT_EQ(mesh.positions[mesh.indices[k]], before.positions[before.indices[k]]);

  // A sheet touching itself there (three faces of one sheet) is not this case.
  PolygonMesh sphere = testing::icosphere(1);
  EXPECT_TRUE(pair_sheets_ending_on_edges(sphere).empty());
}

TEST(SheetEnds, ARoomsWallsAndFloorMapAsSheetsNotAsOneEnvelope) {
  PolygonMesh mesh = floor_and_walls(6, 2.5);
  ASSERT_EQ(analyze_topology(mesh).non_manifold_edges, 3u + 3u);
  PolygonMesh shared = mesh;
  EXPECT_EQ(split_non_manifold_edges(shared).edges_split, 0u);  // one wall face per edge

  PolygonMesh input = mesh;
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.preparation.edges_split, 6u);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped whole
  for (const PartReport& part : prepared.parts) EXPECT_FALSE(part.wrapped);
  EXPECT_EQ(prepared.parts.size(), 3u);  // the floor, each wall: each doubled
  EXPECT_EQ(prepared.preparation.sheets_doubled, 3u);
  ASSERT_TRUE(input_failures(prepared).empty()) << input_failures(prepared).front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

}  // namespace
}  // namespace spheremap
