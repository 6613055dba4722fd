// Closing handles (core/prepare/handle_closing.h): parts of genus g > 0 are cut along short
// non-separating cycles and both sides filled until genus 0, within the cycle and genus
// bounds (the message says which one stopped it, with the numbers); the map is certified,
// the sphere in the input's layout too (with the input vertices on the cut copied); meshes
// of genus 0 are untouched.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "core/io/gltf_reader.h"
#include "core/io/mesh_file.h"
#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/surface_distance.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/handle_closing.h"
#include "core/prepare/prepare_mesh.h"
#include "core/prepare/vertex_copies.h"
#include "tests/corpus.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

PrepareOptions repair() {
  PrepareOptions options;
  options.method = PrepareMethod::kRepair;
  return options;
}

// Maps `input` under `options`, expecting every handle closed and the map certified, in
// the welded layout and the input's own (which leaves the fills out).
void expect_closed_and_certified(PolygonMesh input, size_t genus, const PrepareOptions& options) {
  const size_t input_vertices = input.vertex_count();
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.handles_closed, genus);
  EXPECT_EQ(prepared.preparation.handles_left, 0u);
  EXPECT_GT(prepared.preparation.largest_handle_cycle, 0);
  EXPECT_LE(prepared.preparation.largest_handle_cycle, options.max_handle_cycle);
  EXPECT_EQ(analyze_topology(prepared.welded.mesh).genus(), 0);
  // The input vertices on each cut got a copy for the other side.
  EXPECT_GT(input.vertex_count(), input_vertices);
  EXPECT_EQ(prepared.welded.input_to_welded.size(), input.vertex_count());
  const std::vector<ValidationFailure> failures = input_failures(prepared);
  ASSERT_TRUE(failures.empty()) << failures.front().message;
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const SphereAsset original = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(original.metrics["bijective"]);
  EXPECT_EQ(original.written.folds, 0u);
  EXPECT_EQ(original.written.triangles + prepared.preparation.faces_added,
            mapped.map.check.triangles);
  EXPECT_EQ(original.metrics["preparation"]["handles_closed"], genus);
  const SphereAsset welded = sphere_asset(input, mapped, {}, SphereLayout::kWelded, 0);
  EXPECT_TRUE(welded.metrics["bijective"]);
}

TEST(HandleClosing, ATorusIsClosedToGenusZeroAndMapsCertified) {
  expect_closed_and_certified(testing::torus(12, 24), 1, repair());
  expect_closed_and_certified(testing::torus(12, 24), 1, PrepareOptions{});  // parts
}

// The remesh of a torus whose handle was capped crosses the caps: its distance to the
// input is as far as the cap is wide, not the 1% it is from the capped surface, and the
// metrics must say the former (measured to the input's own faces, as the benchmark does).
TEST(HandleClosing, TheRemeshDistanceIsToTheInputsOwnFacesNotItsCaps) {
  PolygonMesh input = testing::torus(12, 24);
  const PolygonMesh torus = input;
  const PreparedMesh prepared = prepare_input(input, nullptr, PrepareOptions{});
  ASSERT_EQ(prepared.preparation.handles_closed, 1u);
  const MappedMesh mapped = map_prepared(prepared, {});
  const RemeshAsset remesh = remesh_asset(mapped, 64, 1);
  const nlohmann::json& distance = remesh.metrics["distance"];

  const PolygonMesh remeshed = read_gltf(std::span<const uint8_t>(
      reinterpret_cast<const uint8_t*>(remesh.glb.data()), remesh.glb.size()));
  const SurfaceDistance expected =
      surface_distance(torus.positions, fan_triangulate(torus).triangles, remeshed.positions,
                       fan_triangulate(remeshed).triangles, 1);
  EXPECT_NEAR(distance["hausdorff"].get<double>(), expected.hausdorff, 1e-6);
  const double to_caps = remesh.metrics["distance_to_prepared"]["hausdorff"].get<double>();
  EXPECT_GT(distance["hausdorff"].get<double>(), 3 * to_caps);
}

TEST(HandleClosing, PlatesWithThroughHolesAreClosedEveryOne) {
  // Two holes: a double torus; three: a printer bed's plate.
  expect_closed_and_certified(testing::plate_with_holes(5, 3, {{1, 1}, {3, 1}}), 2, repair());
  expect_closed_and_certified(testing::plate_with_holes(7, 3, {{1, 1}, {3, 1}, {5, 1}}), 3,
                              repair());
  // A wide hole: every short cycle has collinear corners (as along CAD edges), which the
  // fills go around instead of making triangles of no area.
  expect_closed_and_certified(testing::plate_with_holes(6, 6, {{2, 2}, {3, 2}, {2, 3}, {3, 3}}), 1,
                              repair());
}

TEST(HandleClosing, TheCutsAreSimpleCyclesOfCopiedVerticesAndTheFillsCloseThem) {
  PolygonMesh mesh = weld(testing::plate_with_holes(7, 3, {{1, 1}, {3, 1}, {5, 1}}), 0).mesh;
  const size_t vertices = mesh.vertex_count(), faces = mesh.face_count();
  const HandleClosing closed = close_handles(mesh, 1.0);
  EXPECT_EQ(closed.handles_closed, 3u);
  EXPECT_EQ(mesh.vertex_count(), vertices + closed.copy_of.size());
  EXPECT_EQ(mesh.face_count(), faces + closed.faces_added);
  for (size_t k = 0; k < closed.copy_of.size(); ++k) {
    ASSERT_LT(closed.copy_of[k], vertices);
    EXPECT_EQ(mesh.positions[vertices + k], mesh.positions[closed.copy_of[k]]);
  }
  // Each hole's rim (4 corners) is the shortest cycle: 4 copies and 2 x 2 triangles each.
  EXPECT_EQ(closed.copy_of.size(), 12u);
  EXPECT_EQ(closed.faces_added, 12u);
  EXPECT_DOUBLE_EQ(closed.largest_cycle, 4 / std::sqrt(49.0 + 9 + 1));
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_TRUE(topology.closed() && topology.manifold());
  EXPECT_EQ(topology.inconsistent_edges, 0u);
  EXPECT_EQ(topology.genus(), 0);
}

// A thin plate's hole: its rim (4 long) is the shortest cycle, but a cap across it lies half
// the hole's width (5% of the diagonal) from the plate; a cycle through the hole and around
// the wall beside it (longer) is capped inside the material, as far as the plate is thin.
// The remesh of the plate follows: within 2% of the input where the rim's cap left 5%.
TEST(HandleClosing, AThinPlatesHoleIsCutThroughItsWallWhereTheCapStaysNear) {
  const PolygonMesh plate = weld(testing::plate_with_holes(7, 7, {{3, 3}}, 0.1), 0).mesh;
  const double diagonal = std::sqrt(49.0 + 49 + 0.01);
  PolygonMesh mesh = plate;
  const HandleClosing closed = close_handles(mesh, 1.5);
  ASSERT_EQ(closed.handles_closed, 1u);
  EXPECT_LE(closed.farthest_fill, 0.05 / diagonal + 1e-9);
  EXPECT_EQ(analyze_topology(mesh).genus(), 0);

  PolygonMesh input = plate;
  const PreparedMesh prepared = prepare_input(input, nullptr, repair());
  ASSERT_EQ(prepared.preparation.handles_closed, 1u);
  EXPECT_DOUBLE_EQ(prepared.preparation.farthest_handle_fill, closed.farthest_fill);
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_TRUE(certify(mapped, mapped.float32_check).certified);
  const RemeshAsset remesh = remesh_asset(mapped, 128, 1);
  EXPECT_LT(remesh.metrics["distance"]["hausdorff"].get<double>(), 0.02);
}

// A plate's through-hole is closed by two fills at the same place (Reach I noted "two
// coincident fills"): one per side of the cut, with opposite normals. Both are needed: with
// one, the other side's loop stays open; one fill across the uncut rim instead gives each
// rim edge a third face.
TEST(HandleClosing, AThroughHoleGetsTwoCoincidentCapsAndNeedsBoth) {
  const PolygonMesh plate = weld(testing::plate_with_holes(3, 3, {{1, 1}}), 0).mesh;
  PolygonMesh mesh = plate;
  const size_t faces = mesh.face_count();
  const HandleClosing closed = close_handles(mesh, 1.0);
  ASSERT_EQ(closed.handles_closed, 1u);
  ASSERT_EQ(closed.faces_added, 4u);  // the 1 x 1 rim: 2 triangles per side
  auto vector_area = [&](size_t first, size_t count) {
    Vec3 sum{0, 0, 0};
    for (size_t f = first; f < first + count; ++f) {
      const auto c = mesh.face(f);
      sum += 0.5 * cross(mesh.positions[c[1]] - mesh.positions[c[0]],
                         mesh.positions[c[2]] - mesh.positions[c[0]]);
    }
    return sum;
  };
  const Vec3 one = vector_area(faces, 2), other = vector_area(faces + 2, 2);
  EXPECT_NEAR(norm(one), 1.0, 1e-12);
  EXPECT_NEAR(norm(other), 1.0, 1e-12);
  EXPECT_NEAR(norm(one + other), 0.0, 1e-12);  // the same square, facing away
  EXPECT_EQ(analyze_topology(mesh).genus(), 0);

  PolygonMesh one_cap;
  one_cap.positions = mesh.positions;
  for (size_t f = 0; f < faces + 2; ++f) one_cap.add_face(mesh.face(f));
  EXPECT_EQ(analyze_topology(one_cap).boundary_edges, 4u);
  PolygonMesh uncut = plate;
  for (size_t f = faces; f < faces + 2; ++f) {
    std::vector<uint32_t> corners;
    for (uint32_t v : mesh.face(f))
      corners.push_back(v < plate.vertex_count() ? v : closed.copy_of[v - plate.vertex_count()]);
    uncut.add_face(corners);
  }
  EXPECT_EQ(analyze_topology(uncut).non_manifold_edges, 4u);
}

TEST(HandleClosing, TheBoundsStopItAndTheMessageSaysWhichWithTheNumbers) {
  // A ring whose shortest non-separating cycle is 0.713 of its diagonal.
  PolygonMesh ring = testing::torus(12, 24);
  PrepareOptions tight = repair();
  tight.max_handle_cycle = 0.25;
  const PreparedMesh prepared = prepare_input(ring, nullptr, tight);
  EXPECT_EQ(prepared.preparation.handles_closed, 0u);
  EXPECT_EQ(prepared.preparation.handles_left, 1u);
  const std::vector<ValidationFailure> failures = input_failures(prepared);
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "genus");
  EXPECT_NE(failures.front().message.find("max_handle_cycle 0.25"), std::string::npos)
      << failures.front().message;
  EXPECT_NE(failures.front().message.find("is 0.713 of"), std::string::npos)
      << failures.front().message;

  // The genus cap: a plate of 3 holes with a cap of 2 is left as it is.
  PolygonMesh plate = weld(testing::plate_with_holes(7, 3, {{1, 1}, {3, 1}, {5, 1}}), 0).mesh;
  const PolygonMesh before = plate;
  const HandleClosing capped = close_handles(plate, 1.0, nullptr, 2);
  EXPECT_EQ(capped.handles_closed, 0u);
  EXPECT_EQ(capped.handles_left, 3u);
  ASSERT_EQ(capped.stopped.size(), 1u);
  EXPECT_EQ(capped.stopped[0].reason,
            "its genus 3 is above the 2 handles closed in a part of 68 faces (at most 2, and "
            "faces x handles at most 16777216)");
  EXPECT_EQ(plate.indices, before.indices);

  // Under parts, the part left out says it too.
  PolygonMesh two = testing::assembled(
      {{testing::torus(12, 24), {0, 0, 0}}, {testing::icosphere(2), {10, 0, 0}}});
  PrepareOptions parts;
  parts.max_handle_cycle = 0.25;
  const PreparedMesh both = prepare_input(two, nullptr, parts);
  ASSERT_EQ(both.parts.size(), 2u);
  EXPECT_EQ(both.parts_left_out(), 1u);
  bool said = false;
  for (const PartReport& part : both.parts)
    for (const ValidationFailure& f : part.failures)
      said |= f.check == "genus" && f.message.find("max_handle_cycle 0.25") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(HandleClosing, ExactStillRefusesAndZeroClosesNone) {
  PolygonMesh ring = testing::torus(12, 24);
  PrepareOptions exact;
  exact.method = PrepareMethod::kExact;
  const PreparedMesh refused = prepare_input(ring, nullptr, exact);
  EXPECT_EQ(refused.preparation.handles_closed, 0u);
  EXPECT_EQ(input_failures(refused).front().check, "genus");
  PrepareOptions none = repair();
  none.max_handle_cycle = 0;
  EXPECT_EQ(input_failures(prepare_input(ring, nullptr, none)).front().check, "genus");
  EXPECT_EQ(ring.vertex_count(), testing::torus(12, 24).vertex_count());
}

TEST(HandleClosing, AGlTFInputKeepsItsLookWithTheCutVerticesCopiedInItsPrimitive) {
  const std::string file = testing::textured_glb(testing::torus(12, 24));
  GltfAppearance look;
  PolygonMesh input = read_gltf(testing::as_bytes(file), {}, nullptr, nullptr, &look);
  const size_t input_vertices = input.vertex_count();
  const PreparedMesh prepared = prepare_input(input, &look, repair());
  ASSERT_EQ(prepared.preparation.handles_closed, 1u);
  ASSERT_EQ(look.primitives.size(), 1u);
  EXPECT_EQ(look.primitives[0].vertex_count, input.vertex_count());
  // This file stores each triangle's corners apart: every input vertex on the cut has its
  // faces on one side and moves with them, so no copy is needed.
  EXPECT_EQ(input.vertex_count(), input_vertices);
  for (const GltfAppearance::Attribute& a : look.attributes)
    EXPECT_EQ(a.values.size(), size_t(a.components) * input.vertex_count()) << a.name;
  const MappedMesh mapped = map_prepared(prepared, {});
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0, &look);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(sphere.written.folds, 0u);
}

TEST(HandleClosing, InputVertexCopiesGoToTheEndOfTheirPrimitiveWithTheirAttributes) {
  // Primitive 0: vertices 0-3 (two triangles), primitive 1: vertices 4-6. Face 1 uses a
  // copy of vertex 2 (index 7, not yet in the mesh).
  PolygonMesh input;
  for (int v = 0; v < 7; ++v) input.positions.push_back({double(v), 0, 0});
  input.add_face(std::vector<uint32_t>{0, 1, 2});
  input.add_face(std::vector<uint32_t>{7, 3, 1});
  input.add_face(std::vector<uint32_t>{4, 5, 6});
  GltfAppearance look;
  look.primitives.resize(2);
  look.primitives[0].vertex_count = 4;
  look.primitives[0].face_count = 2;
  look.primitives[1].first_vertex = 4;
  look.primitives[1].vertex_count = 3;
  look.primitives[1].first_face = 2;
  look.primitives[1].face_count = 1;
  look.attributes.push_back({"TEXCOORD_0", 2, {0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6}});
  std::vector<uint32_t> to_welded = {0, 1, 2, 3, 4, 5, 6, 9};
  insert_vertex_copies(input, &look, {2}, to_welded);
  ASSERT_EQ(input.vertex_count(), 8u);
  EXPECT_EQ(input.positions[4], input.positions[2]);  // the copy, at its primitive's end
  EXPECT_EQ(input.indices, (std::vector<uint32_t>{0, 1, 2, 4, 3, 1, 5, 6, 7}));
  EXPECT_EQ(to_welded, (std::vector<uint32_t>{0, 1, 2, 3, 9, 4, 5, 6}));
  EXPECT_EQ(look.primitives[0].vertex_count, 5u);
  EXPECT_EQ(look.primitives[1].first_vertex, 5u);
  EXPECT_EQ(look.primitives[1].vertex_count, 3u);
  EXPECT_EQ(look.attributes[0].values,
            (std::vector<float>{0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 4, 4, 5, 5, 6, 6}));
}

TEST(HandleClosing, AGenusZeroMeshIsUntouched) {
  for (const PolygonMesh& shape :
       {testing::icosphere(3), testing::horseshoe(), testing::quad_cube(4)}) {
    PolygonMesh mesh = weld(shape, 0).mesh;
    const PolygonMesh before = mesh;
    const HandleClosing closed = close_handles(mesh, 1.0);
    EXPECT_EQ(closed.handles_closed + closed.handles_left, 0u);
    EXPECT_EQ(mesh.positions, before.positions);
    EXPECT_EQ(mesh.indices, before.indices);
  }
  // An asset of two genus-0 parts goes through the closing (it fails the components
  // check): its sphere is the same, byte for byte, as with the closing off.
  auto sphere_of = [](double max_handle_cycle) {
    PolygonMesh input = testing::assembled(
        {{testing::icosphere(2), {0, 0, 0}}, {testing::horseshoe(), {10, 0, 0}}});
    PrepareOptions parts;
    parts.max_handle_cycle = max_handle_cycle;
    const PreparedMesh prepared = prepare_input(input, nullptr, parts);
    EXPECT_EQ(prepared.preparation.handles_closed + prepared.preparation.handles_left, 0u);
    const MappedMesh mapped = map_prepared(prepared, {});
    return sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0).glb;
  };
  EXPECT_EQ(sphere_of(1.0), sphere_of(0));
}

TEST(HandleClosing, TheCorpusMeshesOfGenusZeroAreUntouched) {
  SKIP_WITHOUT_CORPUS("MANIFEST.md");
  size_t meshes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(testing::corpus_dir())) {
    if (entry.path().extension() != ".obj") continue;
    PolygonMesh mesh = weld(read_mesh_file(entry.path().string()), 0).mesh;
    if (analyze_topology(mesh).genus() != 0) continue;
    const PolygonMesh before = mesh;
    const HandleClosing closed = close_handles(mesh, 1.0);
    EXPECT_EQ(closed.handles_closed + closed.handles_left, 0u) << entry.path();
    EXPECT_EQ(mesh.positions, before.positions) << entry.path();
    EXPECT_EQ(mesh.indices, before.indices) << entry.path();
    ++meshes;
  }
  EXPECT_GT(meshes, 10u);
}

}  // namespace
}  // namespace spheremap
