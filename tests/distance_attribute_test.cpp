// The morph of an envelope carries each vertex's distance to the ORIGINAL surface as the
// `_DISTANCE` vertex attribute (original_surface.h, vertex_distances), which the page draws
// as a heat map; a mesh mapped as it is carries none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/map/pipeline.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/map_outputs.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

struct ReadGlb {
  nlohmann::json json;
  std::string bin;
};

// The JSON and BIN chunks of a GLB as the writer lays them out (JSON first, then BIN).
ReadGlb read_glb(const std::string& glb) {
  ReadGlb out;
  uint32_t json_length = 0, bin_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  out.json = nlohmann::json::parse(glb.substr(20, json_length));
  const size_t bin_start = 20 + json_length;
  if (bin_start + 8 <= glb.size()) {
    std::memcpy(&bin_length, glb.data() + bin_start, 4);
    out.bin = glb.substr(bin_start + 8, bin_length);
  }
  return out;
}

// The floats of mesh `mesh`'s attribute `name` (empty when it has none): SCALAR, or VEC3
// (x, y, z of each vertex in turn) when `components` is 3.
std::vector<float> attribute(const ReadGlb& glb, const std::string& name, size_t mesh = 0,
                             size_t components = 1) {
  const nlohmann::json& attributes = glb.json["meshes"][mesh]["primitives"][0]["attributes"];
  if (!attributes.contains(name)) return {};
  const nlohmann::json& accessor = glb.json["accessors"][attributes[name].get<size_t>()];
  EXPECT_EQ(accessor["componentType"], 5126);
  EXPECT_EQ(accessor["type"], components == 3 ? "VEC3" : "SCALAR");
  const nlohmann::json& view = glb.json["bufferViews"][accessor["bufferView"].get<size_t>()];
  std::vector<float> values(accessor["count"].get<size_t>() * components);
  std::memcpy(values.data(), glb.bin.data() + view.value("byteOffset", size_t{0}),
              values.size() * 4);
  return values;
}

TEST(DistanceAttribute, AWrappedMorphCarriesEachVertexDistanceToTheOriginal) {
  PolygonMesh torus = testing::torus(32, 16);
  const PolygonMesh original = torus;
  PrepareOptions prepare;
  prepare.method = PrepareMethod::kWrap;
  prepare.envelope.resolution = 96;
  prepare.envelope.target_faces = 3000;
  const MappedMesh mapped = map_prepared(prepare_input(torus, nullptr, prepare), {});
  ASSERT_TRUE(mapped.map.check.bijective);
  const MorphAsset morph = morph_asset(mapped);
  const ReadGlb glb = read_glb(morph.glb);
  const std::vector<float> distances = attribute(glb, "_DISTANCE");
  const PolygonMesh& envelope = mapped.prepared.welded.mesh;
  ASSERT_EQ(distances.size(), envelope.vertex_count());
  ASSERT_TRUE(morph.metrics.contains("vertex_distances"));
  const nlohmann::json& m = morph.metrics["vertex_distances"];
  EXPECT_EQ(m["attribute"], "_DISTANCE");
  EXPECT_TRUE(glb.json["meshes"][0]["extras"]["spheremap_morph"].contains("vertex_distances"));

  // Independently: every envelope vertex against every original triangle (no tree),
  // relative to the original's bounding-box diagonal.
  Vec3 lo = original.positions[0], hi = lo;
  for (const Vec3& p : original.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double diagonal = norm(hi - lo);
  const std::vector<Triangle> triangles = fan_triangulate(original).triangles;
  double brute_max = 0;
  size_t off = 0;
  for (size_t v = 0; v < envelope.vertex_count(); ++v) {
    const Vec3& p = envelope.positions[v];
    double best = std::numeric_limits<double>::max();
    for (const Triangle& t : triangles) {
      const Vec3 q = closest_on_triangle(p, original.positions[t[0]], original.positions[t[1]],
                                         original.positions[t[2]]);
      best = std::min(best, norm(p - q));
    }
    const double relative = best / diagonal;
    brute_max = std::max(brute_max, relative);
    off += std::abs(distances[v] - relative) > 1e-5;
  }
  std::printf("envelope vertices %zu, max distance %.5f (brute force %.5f), rms %.5f, %.4f s\n",
              distances.size(), m["max"].get<double>(), brute_max, m["rms"].get<double>(),
              m["seconds"].get<double>());
  EXPECT_EQ(off, 0u);
  EXPECT_NEAR(m["max"].get<double>(), brute_max, 1e-6);
  EXPECT_NEAR(m["diagonal"].get<double>(), diagonal, 1e-9 * diagonal);
  // The envelope lies off the torus (an offset of a voxel or so), and not far off: the
  // filled hole is within a few voxels' reach of the original.
  EXPECT_GT(brute_max, 0.5 / 96);
  EXPECT_LT(brute_max, 0.5);
}

// Auto wraps an open dome beside a sphere: the dome's mesh carries _DISTANCE to the dome's
// own faces (relative to their diagonal), the sphere's none.
TEST(DistanceAttribute, OnlyTheWrappedPartOfSeveralCarriesIt) {
  const PolygonMesh sphere = testing::icosphere(2), dome = testing::dome(3);
  PolygonMesh input = testing::assembled({{sphere, {0, 0, 0}}, {dome, {3, 0, 0}}});
  const PolygonMesh original = input;
  PrepareOptions prepare;
  prepare.method = PrepareMethod::kAuto;
  prepare.double_open_sheets = false;  // the dome stands for a part only an envelope maps
  prepare.envelope.resolution = 96;
  prepare.envelope.target_faces = 3000;
  const MappedMesh mapped = map_prepared(prepare_input(input, nullptr, prepare), {});
  ASSERT_EQ(mapped.prepared.preparation.decided, "parts+wrap");
  ASSERT_EQ(mapped.parts.size(), 2u);
  const MorphAsset morph = morph_asset(mapped, 4, &original, nullptr);
  const ReadGlb glb = read_glb(morph.glb);
  ASSERT_EQ(glb.json["meshes"].size(), 2u);
  size_t with = 0;
  for (size_t k = 0; k < 2; ++k) {
    const std::vector<float> distances = attribute(glb, "_DISTANCE", k);
    if (distances.empty()) continue;
    ++with;
    const std::vector<float> xyz = attribute(glb, "POSITION", k, 3);
    ASSERT_EQ(xyz.size(), 3 * distances.size());
    // Brute force against the dome's faces of the input (the sphere's come first).
    std::vector<Triangle> faces;
    Vec3 lo = original.positions[original.face(sphere.face_count())[0]], hi = lo;
    for (size_t f = sphere.face_count(); f < original.face_count(); ++f) {
      const auto c = original.face(f);
      for (size_t i = 1; i + 1 < c.size(); ++i) faces.push_back({c[0], c[i], c[i + 1]});
      for (uint32_t v : c) {
        const Vec3& p = original.positions[v];
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    }
    const double diagonal = norm(hi - lo);
    double brute_max = 0, attribute_max = 0;
    for (size_t v = 0; v < distances.size(); ++v) {
      const Vec3 p{xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]};
      double best = std::numeric_limits<double>::max();
      for (const Triangle& t : faces)
        best = std::min(best, norm(p - closest_on_triangle(p, original.positions[t[0]],
                                                           original.positions[t[1]],
                                                           original.positions[t[2]])));
      brute_max = std::max(brute_max, best / diagonal);
      attribute_max = std::max(attribute_max, static_cast<double>(distances[v]));
    }
    std::printf("wrapped part: %zu vertices, max %.5f (brute force %.5f)\n", distances.size(),
                attribute_max, brute_max);
    EXPECT_NEAR(attribute_max, brute_max, 1e-5);
    EXPECT_GT(brute_max, 0);
    ASSERT_TRUE(morph.metrics.contains("vertex_distances"));
    EXPECT_NEAR(morph.metrics["vertex_distances"]["max"].get<double>(), attribute_max, 1e-6);
    EXPECT_EQ(morph.metrics["vertex_distances"]["wrapped_parts"], 1);
  }
  EXPECT_EQ(with, 1u);
}

TEST(DistanceAttribute, AnExactMorphCarriesNone) {
  PolygonMesh sphere = testing::icosphere(2);
  const MappedMesh mapped = map_prepared(prepare_input(sphere, nullptr, PrepareOptions{}), {});
  ASSERT_TRUE(mapped.map.check.bijective);
  const MorphAsset morph = morph_asset(mapped);
  EXPECT_TRUE(attribute(read_glb(morph.glb), "_DISTANCE").empty());
  EXPECT_FALSE(morph.metrics.contains("vertex_distances"));
}

}  // namespace
}  // namespace spheremap
