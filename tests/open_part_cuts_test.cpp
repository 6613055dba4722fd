// Open parts of several holes cut into discs (core/prepare/open_part_cuts.h), then closed
// by their back under prepare=auto: checked on the topology the cut leaves, on every
// corner's position (nothing moves), and on the map and remesh of an open pipe.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/open_part_cuts.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/sheet_doubling.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// The mesh without the faces whose index `drop` says.
template <class Drop>
PolygonMesh without_faces(const PolygonMesh& mesh, Drop drop) {
  PolygonMesh out;
  out.positions = mesh.positions;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (!drop(f)) out.add_face(mesh.face(f));
  return out;
}

// capped_tube(16, 24, 12) without its two 16-gon caps: a pipe open at both ends.
PolygonMesh open_pipe() {
  const PolygonMesh tube = testing::capped_tube(16, 24, 12);
  return without_faces(tube, [&](size_t f) { return tube.face_size(f) == 16; });
}

// The cut leaves a disc whose every corner stands where the input's did: faces in order,
// of the same sizes, the input's vertices unmoved and each copy at its source.
void expect_cut_into_disc_in_place(const PolygonMesh& input, size_t loops) {
  ASSERT_EQ(analyze_topology(input).boundary_loops, loops);
  PolygonMesh cut = input;
  const OpenPartCuts cuts = cut_open_parts_into_discs(cut);
  EXPECT_EQ(cuts.parts_cut, 1u);
  EXPECT_EQ(cuts.paths_cut, loops - 1);
  EXPECT_EQ(cut.vertex_count(), input.vertex_count() + cuts.vertices_added);
  EXPECT_GE(cuts.vertices_added, 2 * (loops - 1));  // both ends of every path at least
  EXPECT_TRUE(is_open_disc(analyze_topology(cut)));
  ASSERT_EQ(cut.face_count(), input.face_count());
  for (size_t v = 0; v < input.vertex_count(); ++v) EXPECT_EQ(cut.positions[v], input.positions[v]);
  for (size_t f = 0; f < input.face_count(); ++f) {
    ASSERT_EQ(cut.face_size(f), input.face_size(f));
    for (size_t k = 0; k < input.face_size(f); ++k)
      EXPECT_EQ(cut.positions[cut.face(f)[k]], input.positions[input.face(f)[k]]);
  }
  // Closed by its back, it is a closed genus-0 surface.
  EXPECT_EQ(double_open_sheets(cut).sheets_doubled, 1u);
  const TopologyReport closed = analyze_topology(cut);
  EXPECT_TRUE(mapping_failures(closed).empty());
}

TEST(OpenPartCuts, ABandAPipeAndACubeWithFiveHolesAreCutIntoDiscsInPlace) {
  expect_cut_into_disc_in_place(testing::band(3), 2);
  expect_cut_into_disc_in_place(open_pipe(), 2);
  // A sphere with five holes apart from each other (quads of a cube, one per side but one).
  const PolygonMesh cube = testing::quad_cube(6);
  std::vector<char> drop(cube.face_count(), 0);
  for (size_t side = 0; side < 5; ++side) drop[side * 36 + 14] = 1;
  expect_cut_into_disc_in_place(without_faces(cube, [&](size_t f) { return drop[f]; }), 5);
}

TEST(OpenPartCuts, OnlyOpenSpheresOfSeveralHolesAreCut) {
  for (const PolygonMesh& other : {testing::dome(2), testing::holed_torus(24, 12),
                                   testing::icosphere(2), testing::torus(16, 8)}) {
    PolygonMesh same = other;
    EXPECT_EQ(cut_open_parts_into_discs(same).parts_cut, 0u);
    EXPECT_EQ(same.positions, other.positions);
    EXPECT_EQ(same.indices, other.indices);
  }
  // A kit of a disc, a band, a holed torus and a sphere: the band alone, its faces where
  // they were in the whole.
  const PolygonMesh kit = testing::assembled({{testing::dome(2), {0, 0, 0}},
                                              {testing::band(2), {3, 0, 0}},
                                              {testing::holed_torus(24, 12), {9, 0, 0}},
                                              {testing::icosphere(1), {15, 0, 0}}});
  PolygonMesh cut = kit;
  EXPECT_EQ(cut_open_parts_into_discs(cut).parts_cut, 1u);
  ASSERT_EQ(cut.face_count(), kit.face_count());
  size_t changed = 0;
  for (size_t f = 0; f < kit.face_count(); ++f)
    for (size_t k = 0; k < kit.face_size(f); ++k) {
      changed += cut.face(f)[k] != kit.face(f)[k];
      EXPECT_EQ(cut.positions[cut.face(f)[k]], kit.positions[kit.face(f)[k]]);
    }
  EXPECT_GT(changed, 0u);
}

// Spheres with random faces taken away (holes that merge, touch at a corner or split the
// sphere): each part the cut takes becomes a disc with every corner where it was; a part it
// leaves is as it was.
TEST(OpenPartCuts, RandomHolesAreCutIntoDiscsOrLeftAsTheyWere) {
  std::mt19937 random(44);
  size_t cut_parts = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const PolygonMesh sphere = testing::icosphere(2);
    std::uniform_int_distribution<size_t> face(0, sphere.face_count() - 1);
    std::vector<char> drop(sphere.face_count(), 0);
    for (int k = 0; k < 2 + trial % 12; ++k) drop[face(random)] = 1;
    const PolygonMesh input = without_faces(sphere, [&](size_t f) { return drop[f]; });
    PolygonMesh cut = input;
    const OpenPartCuts cuts = cut_open_parts_into_discs(cut);
    cut_parts += cuts.parts_cut;
    ASSERT_EQ(cut.face_count(), input.face_count());
    for (size_t f = 0; f < input.face_count(); ++f)
      for (size_t k = 0; k < input.face_size(f); ++k)
        ASSERT_EQ(cut.positions[cut.face(f)[k]], input.positions[input.face(f)[k]]);
    const TopologyReport before = analyze_topology(input), after = analyze_topology(cut);
    if (cuts.parts_cut == 0) {
      EXPECT_EQ(cut.indices, input.indices);
    } else if (before.component_vertices.size() == 1) {
      EXPECT_TRUE(is_open_disc(after)) << "trial " << trial;
    }
  }
  EXPECT_GT(cut_parts, 30u);  // most trials leave one open sphere of several holes
}

// A pipe open at both ends (each hole 4% of its surface, small enough to fill, but a fill
// would stand 8% of its diagonal away): under auto it is cut and closed by its back, maps
// certified, and its remesh stays within 2% of it; in the input's layout the sphere has
// the input's faces only, each corner where the map put its side of the seam.
TEST(OpenPartCuts, AutoMapsAnOpenPipeExactlyByItsCutAndBack) {
  PolygonMesh input = open_pipe();
  const size_t input_faces = input.face_count();
  PrepareOptions automatic;
  automatic.method = PrepareMethod::kAuto;
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic);
  EXPECT_EQ(prepared.preparation.decided, "repair");
  EXPECT_EQ(prepared.preparation.holes_filled, 0u);
  EXPECT_EQ(prepared.preparation.holes_left, 0u);
  EXPECT_EQ(prepared.preparation.open_parts_cut, 1u);
  EXPECT_EQ(prepared.preparation.sheets_doubled, 1u);
  EXPECT_TRUE(prepared.filled.empty());
  EXPECT_EQ(input.face_count(), input_faces);
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  EXPECT_LT(remesh_asset(mapped, 128, 1).metrics["distance"]["hausdorff"].get<double>(), 0.02);
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(sphere.written.triangles, 2 * input_faces);  // quads, two triangles each
  EXPECT_EQ(sphere.metrics["preparation"]["open_parts_cut"], 1);

  // Without backs, its holes are filled: caps far from it.
  PolygonMesh again = open_pipe();
  automatic.double_open_sheets = false;
  const PreparedMesh filled = prepare_input(again, nullptr, automatic);
  EXPECT_EQ(filled.preparation.holes_filled, 2u);
  EXPECT_EQ(filled.preparation.open_parts_cut, 0u);
  const MappedMesh filled_map = map_prepared(filled, {});
  EXPECT_GT(remesh_asset(filled_map, 128, 1).metrics["distance"]["hausdorff"].get<double>(), 0.06);
}

}  // namespace
}  // namespace spheremap
