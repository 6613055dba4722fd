#include <gtest/gtest.h>

#include <cmath>

#include "core/io/mesh_file.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"
#include "core/mesh/topology.h"
#include "tests/corpus.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

std::string first_failure(const PolygonMesh& mesh) {
  auto failures = mapping_failures(analyze_topology(mesh));
  return failures.empty() ? "" : failures[0].check;
}

TEST(Topology, ClosedGenusZeroMeshesPass) {
  for (const PolygonMesh& m :
       {testing::icosphere(2), testing::quad_cube(3), testing::capped_tube(8, 20, 30)}) {
    const TopologyReport r = analyze_topology(m);
    EXPECT_EQ(r.genus(), 0);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_TRUE(mapping_failures(r).empty());
    EXPECT_GT(r.signed_volume, 0);
  }
}

// Far from the origin the divergence-theorem sum adds terms of (distance)^3 into a volume
// of (size)^3: about the origin this mesh's terms are ~1e16 and its volume 4e-9.
TEST(SignedVolume, KeepsItsSignFarFromTheOrigin) {
  PolygonMesh mesh = testing::icosphere(3);
  for (Vec3& p : mesh.positions) p = 1e-3 * p + Vec3{1e5, -2e5, 3e5};
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  EXPECT_GT(signed_volume(mesh.positions, triangles), 0);
  const std::vector<Triangle> flipped = fan_triangulate(testing::reversed(mesh)).triangles;
  EXPECT_LT(signed_volume(mesh.positions, flipped), 0);
  EXPECT_GT(analyze_topology(mesh).signed_volume, 0);
}

TEST(Topology, CountsFacesAndSizes) {
  const TopologyReport r = analyze_topology(testing::capped_tube(8, 20, 30));
  EXPECT_EQ(r.faces, 8u * 20 + 2);
  EXPECT_EQ(r.face_sizes.at(4), 160u);
  EXPECT_EQ(r.face_sizes.at(8), 2u);
  EXPECT_EQ(r.vertices, 8u * 21);
  EXPECT_EQ(r.edges, 8u * 20 + 8u * 21);
}

TEST(Topology, ReportsGenusOfTorus) {
  const TopologyReport r = analyze_topology(testing::torus(8, 12));
  EXPECT_EQ(r.genus(), 1);
  auto failures = mapping_failures(r);
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].check, "genus");
  EXPECT_NE(failures[0].message.find("genus 1"), std::string::npos);
}

TEST(Topology, ReportsHolesWithLoopAndEdgeCounts) {
  PolygonMesh m = testing::without_face(testing::without_face(testing::icosphere(2), 0), 100);
  auto failures = mapping_failures(analyze_topology(m));
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures[0].check, "boundary");
  EXPECT_NE(failures[0].message.find("2 boundary loops (6 boundary edges)"), std::string::npos)
      << failures[0].message;
}

TEST(Topology, ReportsComponentsWithSizes) {
  auto failures = mapping_failures(analyze_topology(testing::two_tetrahedra()));
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_EQ(failures[0].check, "components");
  EXPECT_NE(failures[0].message.find("2 connected components (vertices: 4, 4)"), std::string::npos)
      << failures[0].message;
}

TEST(Topology, FindsPinchedVertexThatEdgeChecksMiss) {
  const TopologyReport r = analyze_topology(testing::pinched_tetrahedra());
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(first_failure(testing::pinched_tetrahedra()), "non_manifold_vertex");
}

TEST(Topology, FindsInconsistentOrientation) {
  PolygonMesh m = testing::icosphere(1);
  std::swap(m.indices[0], m.indices[1]);  // flip one face
  const TopologyReport r = analyze_topology(m);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_EQ(first_failure(m), "orientation");
}

TEST(Topology, InwardOrientationIsValid) {
  const TopologyReport r = analyze_topology(testing::reversed(testing::icosphere(1)));
  EXPECT_LT(r.signed_volume, 0);
  EXPECT_TRUE(mapping_failures(r).empty());
}

// A square closed by its own back (as sheet_doubling makes): the back's centre 1e-12 above
// the front's, so the surface encloses a sliver inside out. Its volume is noise against
// its area: the report says outward, as the map runs it (runs_inward), while a reversed
// sphere is inward.
TEST(Topology, ASurfaceEnclosingNoVolumeIsReportedOutward) {
  PolygonMesh pillow;
  pillow.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 0}, {0, 0, 1e-12}};
  for (uint32_t k = 0; k < 4; ++k) {
    pillow.add_face(std::array<uint32_t, 3>{4, k, (k + 1) % 4});
    pillow.add_face(std::array<uint32_t, 3>{5, (k + 1) % 4, k});
  }
  const TopologyReport r = analyze_topology(pillow);
  ASSERT_TRUE(mapping_failures(r).empty());
  ASSERT_LT(r.signed_volume, 0);  // inside out, by a sliver
  EXPECT_FALSE(r.inward);
  EXPECT_FALSE(runs_inward(pillow.positions, fan_triangulate(pillow).triangles));
  EXPECT_TRUE(analyze_topology(testing::reversed(testing::icosphere(2))).inward);
  EXPECT_FALSE(analyze_topology(testing::icosphere(2)).inward);
}

TEST(Topology, FindsNonFiniteCoordinatesAndRepeatedVertices) {
  PolygonMesh m = testing::icosphere(1);
  m.positions[3].y = INFINITY;
  EXPECT_EQ(first_failure(m), "non_finite");
  PolygonMesh r = testing::icosphere(1);
  r.indices[1] = r.indices[0];
  EXPECT_EQ(first_failure(r), "repeated_vertex");
}

TEST(Topology, RequireMappableThrowsTheFirstCheckWithAllMessages) {
  try {
    require_mappable(analyze_topology(testing::torus(6, 6)));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "genus");
  }
}

// The corpus's bad meshes, each rejected for its own reason (MANIFEST.md).
struct BadMesh {
  const char* file;
  const char* check;
  const char* detail;
};

class CorpusBadMesh : public ::testing::TestWithParam<BadMesh> {};

TEST_P(CorpusBadMesh, IsRejectedForTheRightReason) {
  const BadMesh& bad = GetParam();
  SKIP_WITHOUT_CORPUS(bad.file);
  const PreparedMesh p = prepare_mesh(read_mesh_file(testing::corpus_path(bad.file)), {});
  auto failures = mapping_failures(p.topology);
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures[0].check, bad.check) << failures[0].message;
  EXPECT_NE(failures[0].message.find(bad.detail), std::string::npos) << failures[0].message;
}

INSTANTIATE_TEST_SUITE_P(
    Shared, CorpusBadMesh,
    ::testing::Values(BadMesh{"bad/bunny_holes.obj", "boundary",
                              "5 boundary loops (223 boundary edges)"},
                      BadMesh{"bad/torus.obj", "genus", "genus 1"},
                      BadMesh{"bad/skull_genus2.obj", "genus", "genus 2"},
                      BadMesh{"bad/cow_nmvertex.obj", "non_manifold_vertex", "1 non-manifold"},
                      BadMesh{"bad/tetrahedra5.obj", "components", "5 connected components"}),
    [](const auto& info) {
      std::string name = info.param.file;
      return name.substr(4, name.find('.') - 4);
    });

class CorpusValidMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(CorpusValidMesh, IsAcceptedAsClosedGenusZero) {
  const std::string file = std::string(GetParam()) + ".obj";
  SKIP_WITHOUT_CORPUS(file);
  const PreparedMesh p = prepare_mesh(read_mesh_file(testing::corpus_path(file)), {});
  EXPECT_TRUE(mapping_failures(p.topology).empty());
  EXPECT_EQ(p.topology.genus(), 0);
}

INSTANTIATE_TEST_SUITE_P(Shared, CorpusValidMesh,
                         ::testing::Values("box", "spot_control", "cylinder", "knight",
                                           "horse_quad", "spot_quad", "duck", "spot", "cheburashka",
                                           "hand", "beast", "armadillo", "horse", "scorpion",
                                           "igea"));

TEST(CorpusTopology, HorseIsInward) {
  SKIP_WITHOUT_CORPUS("horse.obj");
  const PreparedMesh p = prepare_mesh(read_mesh_file(testing::corpus_path("horse.obj")), {});
  EXPECT_LT(p.topology.signed_volume, 0);
}

TEST(CorpusTopology, BeastHasItsManifestCounts) {
  SKIP_WITHOUT_CORPUS("beast.obj");
  const PreparedMesh p = prepare_mesh(read_mesh_file(testing::corpus_path("beast.obj")), {});
  EXPECT_EQ(p.topology.vertices, 32311u);
  EXPECT_EQ(p.topology.face_sizes.at(3), 124u);
  EXPECT_EQ(p.topology.face_sizes.at(4), 32228u);
  EXPECT_EQ(p.topology.face_sizes.at(5), 10u);
  EXPECT_EQ(p.topology.face_sizes.at(6), 2u);
}

}  // namespace
}  // namespace spheremap
