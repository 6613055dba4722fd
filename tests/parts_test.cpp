// Assets of several parts (prepare "parts"): every closed genus-0 part mapped and
// certified on a sphere of its own, the others left out with their reasons, and every
// output holding one node per part.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/io/gltf_reader.h"
#include "core/map/certification.h"
#include "core/map/map_parts.h"
#include "core/map/pipeline.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using testing::assembled;

// A sphere (320 faces), two small far tetrahedra, a horseshoe, and an open dome (its hole
// too large to close).
PolygonMesh kit() {
  return assembled({{testing::icosphere(2), {0, 0, 0}},
                    {testing::two_tetrahedra(), {0, 10, 0}},
                    {testing::horseshoe(), {20, 0, 0}},
                    {testing::dome(2), {0, 0, 8}}});
}

std::span<const uint8_t> bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

MappedMesh map_parts_of(PolygonMesh input, MapOptions options = {}) {
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  EXPECT_TRUE(input_failures(prepared).empty());
  return map_prepared(prepared, options);
}

TEST(ConnectedParts, SplitsLargestFirstKeepingEachPartsFaces) {
  const PolygonMesh mesh = kit();
  const std::vector<MeshPart> parts = connected_parts(mesh);
  ASSERT_EQ(parts.size(), 5u);  // two_tetrahedra is two parts
  for (size_t k = 1; k < parts.size(); ++k)
    EXPECT_GE(parts[k - 1].mesh.face_count(), parts[k].mesh.face_count());
  size_t faces = 0;
  for (const MeshPart& part : parts) {
    faces += part.mesh.face_count();
    for (size_t v = 0; v < part.vertex.size(); ++v)
      EXPECT_EQ(part.mesh.positions[v], mesh.positions[part.vertex[v]]);
  }
  EXPECT_EQ(faces, mesh.face_count());
}

TEST(PrepareParts, KeepsThePartsThatMapAndListsTheOthersWithTheirReasons) {
  PolygonMesh input = kit();
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  ASSERT_EQ(prepared.parts.size(), 5u);
  EXPECT_EQ(prepared.parts_left_out(), 1u);
  size_t kept_faces = 0;
  for (const PartReport& part : prepared.parts) {
    if (part.mappable()) {
      kept_faces += part.faces;
    } else {
      EXPECT_EQ(part.failures.front().check, "boundary");
      EXPECT_EQ(part.faces, testing::dome(2).face_count());
    }
  }
  EXPECT_EQ(prepared.welded.mesh.face_count(), kept_faces);
  EXPECT_EQ(prepared.topology.component_vertices.size(), 4u);
  EXPECT_TRUE(remaining_failures(prepared).empty());
  const nlohmann::json report = topology_json(prepared);
  EXPECT_TRUE(report["mappable"]);
  EXPECT_EQ(report["parts"].size(), 5u);

  // repair keeps the one-part rule: the parts are checked, none dropped, and the refusal
  // names parts as the fix with what it would map.
  PolygonMesh again = kit();
  PrepareOptions repair;
  repair.method = PrepareMethod::kRepair;
  const PreparedMesh one_part = prepare_input(again, nullptr, repair);
  EXPECT_EQ(one_part.parts.size(), 5u);
  EXPECT_EQ(one_part.welded.mesh.face_count(), again.face_count());
  const auto failures = input_failures(one_part);
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "boundary");
  const auto components = std::find_if(failures.begin(), failures.end(),
                                       [](const auto& f) { return f.check == "components"; });
  ASSERT_NE(components, failures.end());
  EXPECT_EQ(components->fix.option, "prepare");
  EXPECT_EQ(components->fix.plain_value(), "parts");
  EXPECT_NE(components->fix.effect.find("maps 4 of its 5 parts"), std::string::npos)
      << components->fix.effect;
}

TEST(PrepareParts, RefusesAnAssetNoPartOfWhichMapsAndSaysWhatTheyFail) {
  PolygonMesh input = assembled({{testing::dome(2), {}}, {testing::torus(12, 8), {5, 0, 0}}});
  PrepareOptions no_handles;  // the torus's handle left
  no_handles.max_handle_cycle = 0;
  const PreparedMesh prepared = prepare_input(input, nullptr, no_handles);
  EXPECT_EQ(prepared.parts_left_out(), 2u);
  const auto failures = input_failures(prepared);
  const auto components = std::find_if(failures.begin(), failures.end(),
                                       [](const auto& f) { return f.check == "components"; });
  ASSERT_NE(components, failures.end());
  EXPECT_NE(components->message.find("none of its parts maps alone"), std::string::npos)
      << components->message;
  EXPECT_NE(components->message.find("genus 1"), std::string::npos) << components->message;
  EXPECT_THROW(map_prepared(prepared, {}), InputError);
}

TEST(MapParts, CertifiesEveryPartOnItsOwnSphere) {
  const MappedMesh mapped = map_parts_of(kit());
  ASSERT_EQ(mapped.parts.size(), 4u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  EXPECT_NEAR(mapped.map.check.signed_area_sum, 4 * 4 * M_PI, 1e-6);
  for (const MappedPart& part : mapped.parts) {
    EXPECT_TRUE(certify(part.mapped, part.mapped.float32_check).certified);
    EXPECT_GT(part.radius, 0);
    for (size_t v = 0; v < part.whole_vertex.size(); ++v)
      EXPECT_EQ(mapped.map.sphere[part.whole_vertex[v]], part.mapped.map.sphere[v]);
  }
  // The horseshoe's sphere is about where the horseshoe is.
  const auto horseshoe = std::find_if(mapped.parts.begin(), mapped.parts.end(),
                                      [](auto& p) { return p.center.x > 15; });
  ASSERT_NE(horseshoe, mapped.parts.end());
  const nlohmann::json metrics = metrics_json(mapped, {});
  EXPECT_EQ(metrics["parts_mapped"], 4);
  EXPECT_EQ(metrics["parts_left_out"], 1);
  size_t left_out = 0;
  for (const auto& part : metrics["parts"])
    if (!part["mapped"]) {
      ++left_out;
      EXPECT_EQ(part["check"], "boundary");
      EXPECT_EQ(part["faces"], testing::dome(2).face_count());
    } else {
      EXPECT_TRUE(part["bijective"]);
    }
  EXPECT_EQ(left_out, 1u);
}

// A part whose map is not certified is left out with the reason when another part is
// certified: here the paper's method with no smoothing at all, which maps the convex
// sphere (its radial projection) but folds the horseshoe.
// Progress names the part being mapped, so a progress bar can run over all of them (each
// part's levels count from 0 again).
TEST(MapParts, ProgressNamesThePartBeingMapped) {
  PolygonMesh input = kit();
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  std::vector<size_t> seen;  // the part of each progress report
  size_t parts = 0;
  MapControl control;
  control.on_progress = [&](const MapProgress& p) {
    seen.push_back(p.part);
    parts = p.parts;
  };
  const MappedMesh mapped = map_prepared(prepared, {}, control);
  ASSERT_EQ(mapped.parts.size(), 4u);
  EXPECT_EQ(parts, 4u);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front(), 1u);
  EXPECT_EQ(seen.back(), 4u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  // One mesh: no part named.
  bool named = false;
  control.on_progress = [&](const MapProgress& p) { named |= p.parts != 0 || p.part != 0; };
  map_prepared(prepare_mesh(testing::icosphere(2), {}), {}, control);
  EXPECT_FALSE(named);
}

TEST(MapParts, APartWhoseMapIsNotCertifiedIsLeftOutWithTheReason) {
  PolygonMesh input = assembled({{testing::horseshoe(), {}}, {testing::icosphere(2), {10, 0, 0}}});
  MapOptions crippled;
  crippled.method = Method::kPaper;
  crippled.max_iterations = 0;
  crippled.min_level_iterations = 0;
  crippled.presmooth_steps = 0;
  const MappedMesh mapped = map_prepared(prepare_input(input, nullptr, {}), crippled);
  ASSERT_EQ(mapped.parts.size(), 1u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  EXPECT_EQ(mapped.prepared.welded.mesh.face_count(), testing::icosphere(2).face_count());
  EXPECT_EQ(mapped.prepared.parts_left_out(), 1u);
  const nlohmann::json metrics = metrics_json(mapped, crippled);
  EXPECT_EQ(metrics["parts_mapped"], 1);
  bool reported = false;
  for (const auto& part : metrics["parts"])
    if (!part["mapped"]) {
      EXPECT_EQ(part["check"], "not_certified");
      EXPECT_NE(part["reason"].get<std::string>().find("folded"), std::string::npos) << part;
      reported = true;
    }
  EXPECT_TRUE(reported);
  // The sphere written holds the certified part only.
  const SphereAsset sphere = sphere_asset(input, mapped, crippled, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(testing::Glb(sphere.glb).json["nodes"].size(), 1u);
}

TEST(MapParts, OneTimeLimitForAllTheParts) {
  MapOptions options;
  options.time_limit_seconds = 1e-9;
  const MappedMesh mapped = map_parts_of(kit(), options);
  EXPECT_EQ(mapped.map.stop_reason, StopReason::kTimeLimit);
  EXPECT_EQ(certify(mapped, mapped.float32_check).problem, "time_limit");
  EXPECT_EQ(mapped.map.sphere.size(), mapped.prepared.welded.mesh.vertex_count());
}

TEST(MapParts, AMeshOfOnePartMapsAsUnderRepair) {
  PolygonMesh a = testing::horseshoe(), b = testing::horseshoe();
  PrepareOptions repair;
  repair.method = PrepareMethod::kRepair;
  const MappedMesh parts = map_prepared(prepare_input(a, nullptr, {}), {});
  const MappedMesh one = map_prepared(prepare_input(b, nullptr, repair), {});
  EXPECT_TRUE(parts.parts.empty());
  EXPECT_EQ(parts.map.sphere, one.map.sphere);
}

TEST(PartsOutputs, TheSphereHasANodePerPartPlacedWhereThePartIs) {
  const PolygonMesh input = kit();
  const MappedMesh mapped = map_parts_of(input);
  for (const int draco : {0, kDracoBitsAutomatic}) {
    const SphereAsset asset = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, draco);
    EXPECT_TRUE(asset.metrics["bijective"]);
    EXPECT_TRUE(asset.metrics["bijective_as_written"]);
    EXPECT_EQ(asset.written.triangles, mapped.map.check.triangles);
    const testing::Glb glb(asset.glb);
    ASSERT_EQ(glb.json["nodes"].size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      const nlohmann::json& node = glb.json["nodes"][k];
      EXPECT_NEAR(node["translation"][0].get<double>(), mapped.parts[k].center.x, 1e-9);
      EXPECT_NEAR(node["scale"][0].get<double>(), mapped.parts[k].radius, 1e-9);
    }
    // Read with its nodes: every vertex on its part's sphere.
    const PolygonMesh drawn = read_gltf(bytes(asset.glb));
    size_t on_a_sphere = 0;
    for (const Vec3& p : drawn.positions)
      for (const MappedPart& part : mapped.parts)
        if (std::abs(norm(p - part.center) - part.radius) < 1e-3 * part.radius) {
          ++on_a_sphere;
          break;
        }
    EXPECT_EQ(on_a_sphere, drawn.positions.size());
  }
}

TEST(PartsOutputs, RemeshUvAndMorphHoldEveryPart) {
  const MappedMesh mapped = map_parts_of(kit());
  const RemeshAsset remesh = remesh_asset(mapped, 32);
  EXPECT_TRUE(remesh.metrics["closed_genus0"]);
  EXPECT_EQ(remesh.metrics["unlocated_samples"], 0);
  ASSERT_EQ(remesh.metrics["parts"].size(), 4u);
  int height = 0;
  for (const auto& part : remesh.metrics["parts"]) {
    EXPECT_EQ(part["geometry_image"]["row"], height);
    height += part["geometry_image"]["height"].get<int>();
    EXPECT_GE(part["resolution"].get<int>(), 8);
  }
  EXPECT_EQ(remesh.metrics["geometry_image"]["height"], height);
  EXPECT_EQ(remesh.metrics["parts"][0]["resolution"], 32);
  // Over the asset's diagonal: the farthest part in model units; each part's own figure
  // over its smaller diagonal is larger.
  const nlohmann::json& distance = remesh.metrics["distance"];
  const double asset_diagonal = distance["asset_diagonal"].get<double>();
  double farthest = 0;
  for (const auto& part : remesh.metrics["parts"]) {
    EXPECT_LT(part["distance"]["diagonal"].get<double>(), asset_diagonal);
    farthest = std::max(farthest, part["distance"]["hausdorff"].get<double>() *
                                      part["distance"]["diagonal"].get<double>());
  }
  EXPECT_GT(farthest, 0);
  EXPECT_NEAR(distance["asset_hausdorff"].get<double>(), farthest / asset_diagonal, 1e-12);
  EXPECT_LT(distance["asset_hausdorff"].get<double>(), distance["hausdorff"].get<double>());
  EXPECT_GE(distance["asset_hausdorff_at_most"].get<double>(),
            distance["asset_hausdorff"].get<double>());
  // Each part's grid read back closed and genus 0: four parts once welded.
  const WeldResult back = weld(read_gltf(bytes(remesh.glb)), 0);
  const TopologyReport topology = analyze_topology(back.mesh);
  EXPECT_EQ(topology.component_vertices.size(), 4u);
  EXPECT_TRUE(topology.closed());
  EXPECT_TRUE(topology.manifold());

  const UvAsset uv = uv_asset(mapped);
  EXPECT_EQ(uv.metrics["flipped_triangles"], 0);
  EXPECT_EQ(uv.metrics["atlas"]["cells_per_side"], 2);
  const testing::Glb uv_glb(uv.glb);
  EXPECT_EQ(uv_glb.json["nodes"].size(), 4u);
  EXPECT_EQ(uv_glb.json["materials"].size(), 1u);  // one checker for all

  const MorphAsset morph = morph_asset(mapped, 3);
  const testing::Glb morph_glb(morph.glb);
  EXPECT_EQ(morph_glb.json["nodes"].size(), 4u);
  EXPECT_EQ(morph_glb.json["animations"][0]["channels"].size(), 4u);
}

}  // namespace
}  // namespace spheremap
