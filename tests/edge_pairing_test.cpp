// Non-manifold edges where one surface touches itself (core/prepare/edge_pairing.h): five
// unit cubes in a chain whose ends touch along one edge, as CAD solids meet themselves. The
// four faces there are one sheet, which edge_split cannot share out; paired across their
// solid wedges, each end cube keeps its two faces, the edge splits at its vertices, and
// the chain maps exactly as the ball it is (no face added, no vertex moved). Two cubes
// stacked with the wall between them stored once (core/prepare/interior_walls.h) become two
// closed cubes, the wall doubled.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/edge_pairing.h"
#include "core/prepare/edge_split.h"
#include "core/prepare/hole_filling.h"  // undirected_edge_key
#include "core/prepare/interior_walls.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/vertex_split.h"

namespace spheremap {
namespace {

using Voxel = std::array<int, 3>;

// The boundary of a union of unit cubes: a square (two triangles, outward) on each cube
// side with no cube beyond it, or with the cube beyond across a wall in `walls` (both
// sides stored, lying on each other); corners shared by position. `owner` gets each face's
// cube.
PolygonMesh voxel_surface(const std::vector<Voxel>& voxels, std::vector<size_t>* owner,
                          const std::set<std::pair<Voxel, Voxel>>& walls = {}) {
  const std::set<Voxel> filled(voxels.begin(), voxels.end());
  PolygonMesh mesh;
  std::map<Voxel, uint32_t> id;
  auto at = [&](int x, int y, int z) {
    const auto [it, added] = id.emplace(Voxel{x, y, z}, uint32_t(mesh.positions.size()));
    if (added) mesh.positions.push_back({double(x), double(y), double(z)});
    return it->second;
  };
  for (size_t k = 0; k < voxels.size(); ++k) {
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {0, 1}) {
        Voxel beyond = voxels[k];
        beyond[axis] += side ? 1 : -1;
        if (filled.count(beyond) && !walls.count({voxels[k], beyond}) &&
            !walls.count({beyond, voxels[k]}))
          continue;
        // The square's corners in the plane axis = side, counterclockwise seen from outside.
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        std::array<uint32_t, 4> corner;
        const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
        for (int c = 0; c < 4; ++c) {
          Voxel p = voxels[k];
          p[axis] += side;
          p[u] += du[side ? c : 3 - c];
          p[v] += dv[side ? c : 3 - c];
          corner[c] = at(p[0], p[1], p[2]);
        }
        for (const std::array<uint32_t, 3>& t : {std::array{corner[0], corner[1], corner[2]},
                                                 std::array{corner[0], corner[2], corner[3]}}) {
          mesh.add_face(t);
          if (owner) owner->push_back(k);
        }
      }
  }
  return mesh;
}

// A chain of five cubes from (0,0,0) up and over to (1,1,0): the first and the last touch
// along the edge x = 1, y = 1, z in [0, 1], and nowhere else.
const std::vector<Voxel> kChain = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}};

TEST(EdgePairing, PairsTheFacesAcrossTheirSolidWedges) {
  std::vector<size_t> owner;
  const PolygonMesh mesh = voxel_surface(kChain, &owner);
  const TopologyReport topology = analyze_topology(mesh);
  ASSERT_EQ(topology.non_manifold_edges, 1u);
  ASSERT_EQ(topology.boundary_edges, 0u);
  PolygonMesh shared = mesh;
  EXPECT_EQ(split_non_manifold_edges(shared).edges_split, 0u);  // one sheet: left joined

  const EdgePairs pairs = pair_faces_at_non_manifold_edges(mesh);
  ASSERT_EQ(pairs.size(), 1u);
  const uint64_t edge = pairs.begin()->first;
  const Vec3 a = mesh.positions[edge >> 32], b = mesh.positions[uint32_t(edge)];
  EXPECT_EQ(a.x, 1);
  EXPECT_EQ(a.y, 1);
  EXPECT_EQ(b.x, 1);
  EXPECT_EQ(b.y, 1);
  ASSERT_EQ(pairs.begin()->second.size(), 4u);
  for (const auto& [face, partner] : pairs.begin()->second) {
    EXPECT_NE(face, partner);
    EXPECT_EQ(owner[face], owner[partner]);  // both sides of one end cube
    EXPECT_EQ(paired_face(pairs, edge, partner), face);
  }
  // Paired the other way, each face goes with the other cube's.
  const EdgePairs others = pair_faces_at_non_manifold_edges(mesh, true);
  ASSERT_EQ(others.count(edge), 1u);
  for (const auto& [face, partner] : others.at(edge)) EXPECT_NE(owner[face], owner[partner]);
  // A manifold edge is not in the pairs: every face there is joined.
  EXPECT_EQ(paired_face(pairs, undirected_edge_key(0, 1), 7), 7u);
}

TEST(EdgePairing, TheSplitMakesTheChainOneClosedBallWithNothingMoved) {
  PolygonMesh mesh = voxel_surface(kChain, nullptr);
  const PolygonMesh before = mesh;
  const EdgePairs pairs = pair_faces_at_non_manifold_edges(mesh);
  const VertexSplit split = split_non_manifold_vertices(mesh, nullptr, &pairs);
  // The edge's lower end, where only the end cubes meet; at its upper end the cubes above
  // join both sides into one fan, so that vertex stays one (the edge is two once either end is).
  EXPECT_EQ(split.vertices_added, 1u);
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_edges + topology.non_manifold_vertices, 0u);
  EXPECT_EQ(topology.genus(), 0);
  ASSERT_EQ(mesh.face_count(), before.face_count());
  for (size_t k = 0; k < mesh.indices.size(); ++k)
    EXPECT_EQ(mesh.positions[mesh.indices[k]], before.positions[before.indices[k]]);

  PolygonMesh input = voxel_surface(kChain, nullptr);
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.preparation.edges_split, 1u);
  EXPECT_EQ(prepared.preparation.faces_added, 0u);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);

  // Before this, the chain was wrapped under auto; exact still refuses it.
  PolygonMesh again = voxel_surface(kChain, nullptr);
  PrepareOptions exact;
  exact.method = PrepareMethod::kExact;
  EXPECT_EQ(input_failures(prepare_input(again, nullptr, exact)).front().check,
            "non_manifold_edge");
}

// A ring of eight cubes around a hole, cut by a wall stored on both sides: a C whose ends
// touch face to face, as two solids of a CAD assembly stacked on each other each keep their
// face on the plane they share (MuJoCo's barkour leg: wrapped, 3.4% off). The rim of the
// wall has edges of four faces, two of them lying on each other (running opposite ways):
// taken as an empty wedge of no width between the ends, each end keeps its faces, and the
// C maps exactly as the ball it is (no face added, no vertex moved).
TEST(EdgePairing, FacesOnEachOtherAreTwoSolidsTouching) {
  const std::vector<Voxel> ring = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 0, 1},
                                   {2, 0, 2}, {1, 0, 2}, {0, 0, 2}, {0, 0, 1}};
  const std::set<std::pair<Voxel, Voxel>> cut = {{{0, 0, 0}, {0, 0, 1}}};
  std::vector<size_t> owner;
  const PolygonMesh mesh = voxel_surface(ring, &owner, cut);
  const TopologyReport topology = analyze_topology(mesh);
  ASSERT_EQ(topology.non_manifold_edges, 4u);
  ASSERT_EQ(topology.boundary_edges, 0u);
  PolygonMesh shared = mesh;
  EXPECT_EQ(split_non_manifold_edges(shared).edges_split, 0u);  // one sheet: left joined

  const EdgePairs pairs = pair_faces_at_non_manifold_edges(mesh);
  ASSERT_EQ(pairs.size(), 4u);
  for (const auto& [edge, matched] : pairs) {
    ASSERT_EQ(matched.size(), 4u);
    // Each end of the C with its own faces: cubes 0-3 on one side of the wall, 4-7 on the other.
    for (const auto& [face, partner] : matched) EXPECT_EQ(owner[face] < 4, owner[partner] < 4);
  }

  PolygonMesh input = mesh;
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  EXPECT_EQ(prepared.preparation.faces_added, 0u);
  EXPECT_EQ(prepared.preparation.edges_split, 4u);
  EXPECT_EQ(prepared.preparation.decided, "repair");  // split: not the file's own mesh
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);

  // Two faces on each other running the same way have no order: left out.
  PolygonMesh doubled = voxel_surface({{0, 0, 0}}, nullptr);
  doubled.add_face(std::array{doubled.indices[0], doubled.indices[1], doubled.indices[2]});
  EXPECT_TRUE(pair_faces_at_non_manifold_edges(doubled).empty());
}

// The chain with a flap: a triangle on the touching edge standing out into the empty
// quadrant (x > 1, y < 1), as a scan's stray face does. Five faces at the edge: neither the
// pairing above (an odd count) nor sheet_ends.h (the chain's sheet has four) takes it; the
// last resort pairs the chain's faces as before and lets the flap go, and auto maps both
// (the flap a doubled sheet) instead of wrapping the whole.
TEST(EdgePairing, ALastResortPairsWhatMatchesAndLetsAFlapGo) {
  std::vector<size_t> owner;
  PolygonMesh mesh = voxel_surface(kChain, &owner);
  const uint32_t c = static_cast<uint32_t>(mesh.positions.size());
  std::vector<uint32_t> ends;
  for (uint32_t v = 0; v < mesh.positions.size(); ++v)
    if (mesh.positions[v].x == 1 && mesh.positions[v].y == 1 && mesh.positions[v].z <= 1)
      ends.push_back(v);  // the touching edge's ends, (1, 1, 0) and (1, 1, 1)
  ASSERT_EQ(ends.size(), 2u);
  mesh.positions.push_back({2, 0, 0.5});
  const uint32_t flap = static_cast<uint32_t>(mesh.face_count());
  mesh.add_face(std::array{ends[0], ends[1], c});
  ASSERT_EQ(analyze_topology(mesh).non_manifold_edges, 1u);
  EXPECT_TRUE(pair_faces_at_non_manifold_edges(mesh).empty());  // five faces: not paired

  const EdgePairs pairs = pair_faces_letting_go_of_the_rest(mesh);
  const uint64_t edge = undirected_edge_key(ends[0], ends[1]);
  ASSERT_EQ(pairs.count(edge), 1u);
  EXPECT_EQ(pairs.at(edge).size(), 4u);
  EXPECT_EQ(paired_face(pairs, edge, flap), flap);  // let go
  for (const auto& [face, partner] : pairs.at(edge)) {
    ASSERT_NE(face, flap);
    ASSERT_NE(partner, flap);
    EXPECT_EQ(owner[face], owner[partner]);  // both sides of one end cube, as before
  }

  PolygonMesh input = mesh;
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.original, nullptr);  // not wrapped
  EXPECT_GE(prepared.preparation.edges_split, 1u);
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

// Two cubes stacked, the square between them stored once (facing up, as the lower cube's
// top): its rim edges have three faces. The wall is doubled, each cube closed by one side.
TEST(InteriorWalls, AWallTwoSolidsShareIsDoubledOneSideEach) {
  PolygonMesh mesh = voxel_surface({{0, 0, 0}, {0, 0, 1}}, nullptr);
  const std::array<uint32_t, 4> square = [&] {
    std::array<uint32_t, 4> ids{};
    const Vec3 corners[4] = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int c = 0; c < 4; ++c)
      for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
        if (mesh.positions[v] == corners[c]) ids[c] = v;
    return ids;
  }();
  mesh.add_face(std::array{square[0], square[1], square[2]});
  mesh.add_face(std::array{square[0], square[2], square[3]});
  ASSERT_EQ(analyze_topology(mesh).non_manifold_edges, 4u);
  PolygonMesh shared = mesh;
  EXPECT_EQ(split_non_manifold_edges(shared).edges_split, 0u);  // one face per sheet there

  const PolygonMesh before = mesh;
  const InteriorWalls walls = double_interior_walls(mesh);
  EXPECT_EQ(walls.walls, 1u);
  EXPECT_EQ(walls.faces_added, 2u);
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_edges + topology.non_manifold_vertices, 0u);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_EQ(topology.component_vertices.size(), 2u);  // two closed cubes
  for (size_t k = 0; k < before.indices.size(); ++k)  // nothing moved
    EXPECT_EQ(mesh.positions[mesh.indices[k]], before.positions[before.indices[k]]);

  // Under auto, beside a loose triangle (a hole, so the hole step runs too): the copies are
  // counted in faces_added, and the sphere as written in the input's layout, where the
  // wall is once, is certified like one with fills.
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  PolygonMesh input = before;
  const uint32_t loose = static_cast<uint32_t>(input.vertex_count());
  for (const Vec3& p : {Vec3{5, 0, 0}, Vec3{6, 0, 0}, Vec3{5, 1, 0}}) input.positions.push_back(p);
  input.add_face(std::array{loose, loose + 1, loose + 2});
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.preparation.walls_doubled, 1u);
  EXPECT_EQ(prepared.preparation.decided, "parts");
  EXPECT_EQ(prepared.preparation.faces_added, 2u + 3u);  // the wall's copy, the triangle's back
  EXPECT_EQ(prepared.original, nullptr);
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_EQ(mapped.parts.size(), 3u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);

  // A fin (a triangle standing on a closed cube's edge) is no wall: left as it was.
  PolygonMesh finned = voxel_surface({{0, 0, 0}}, nullptr);
  uint32_t edge[2] = {0, 0};
  for (uint32_t v = 0; v < finned.vertex_count(); ++v) {
    if (finned.positions[v] == Vec3{1, 0, 1}) edge[0] = v;
    if (finned.positions[v] == Vec3{1, 1, 1}) edge[1] = v;
  }
  finned.positions.push_back({1, 0.5, 2});
  finned.add_face(std::array{edge[0], edge[1], uint32_t(finned.vertex_count() - 1)});
  ASSERT_EQ(analyze_topology(finned).non_manifold_edges, 1u);
  const PolygonMesh fin = finned;
  EXPECT_EQ(double_interior_walls(finned).walls, 0u);
  EXPECT_EQ(finned.indices, fin.indices);
}

}  // namespace
}  // namespace spheremap
