// glTF 1.0, read as the glTF 2.0 document it upgrades to (core/io/gltf1_upgrade.h): ids
// for indices, a stride per accessor, a node of several meshes, the GLB 1.0 container,
// the diffuse colour or texture as base colour, and what it refuses.
#include <gtest/gtest.h>

#include <cstring>

#include "core/io/gltf_reader.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using nlohmann::json;
using testing::as_bytes;
using testing::read_error;

// The test icosphere as glTF 1.0 writers stored it: positions and normals interleaved in
// one bufferView (each accessor with byteStride 24 and its own byteOffset), indices in
// another; objects keyed by name; the mesh under a node translated by (10, 0, 0); a red
// KHR_materials_common material. `bin` is the buffer, which `document` holds as a data: URI.
struct Gltf1Sphere {
  nlohmann::json document;
  std::string bin;
  PolygonMesh mesh = testing::icosphere(1);

  Gltf1Sphere() {
    for (const Vec3& p : mesh.positions)
      for (int copy = 0; copy < 2; ++copy)  // the position, then the same as its normal
        for (int k = 0; k < 3; ++k) {
          const float c = static_cast<float>(p[k]);
          bin.append(reinterpret_cast<const char*>(&c), 4);
        }
    const size_t vertex_bytes = bin.size();
    for (uint32_t i : mesh.indices) {
      const uint16_t index = static_cast<uint16_t>(i);
      bin.append(reinterpret_cast<const char*>(&index), 2);
    }
    const size_t vertices = mesh.positions.size();
    document = {{"asset", {{"version", "1.0"}}},
                {"buffers",
                 {{"sphere_buffer",
                   {{"byteLength", bin.size()},
                    {"type", "arraybuffer"},
                    {"uri", "data:application/octet-stream;base64," + testing::base64(bin)}}}}},
                {"bufferViews",
                 {{"vertices",
                   {{"buffer", "sphere_buffer"}, {"byteOffset", 0}, {"byteLength", vertex_bytes}}},
                  {"indices",
                   {{"buffer", "sphere_buffer"},
                    {"byteOffset", vertex_bytes},
                    {"byteLength", bin.size() - vertex_bytes}}}}},
                {"accessors",
                 {{"position", accessor("vertices", 0, 24, 5126, vertices, "VEC3")},
                  {"normal", accessor("vertices", 12, 24, 5126, vertices, "VEC3")},
                  {"index", accessor("indices", 0, 0, 5123, mesh.indices.size(), "SCALAR")}}},
                {"meshes",
                 {{"sphere",
                   {{"primitives",
                     {{{"attributes",
                        {{"POSITION", "position"}, {"NORMAL", "normal"}, {"JOINT", "normal"}}},
                       {"indices", "index"},
                       {"material", "red"},
                       {"mode", 4}}}}}}}},
                {"materials",
                 {{"red",
                   {{"technique", "lambert_technique"},
                    {"extensions",
                     {{"KHR_materials_common",
                       {{"technique", "LAMBERT"}, {"values", {{"diffuse", {1.5, 0, 0}}}}}}}}}}}},
                {"nodes",
                 {{"root",
                   {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}},
                    {"children", {"child"}}}},
                  {"child", {{"meshes", {"sphere"}}}}}},
                {"scenes", {{"main", {{"nodes", {"root"}}}}}},
                {"scene", "main"}};
  }
  static json accessor(const char* view, size_t offset, size_t stride, int type, size_t count,
                       const char* shape) {
    return {{"bufferView", view},    {"byteOffset", offset}, {"byteStride", stride},
            {"componentType", type}, {"count", count},       {"type", shape}};
  }
  std::string text() const { return document.dump(); }
  // The same document in the GLB 1.0 container, its buffer the binary body.
  std::string glb() const {
    json binary = document;
    binary["buffers"] = {{"binary_glTF", {{"byteLength", bin.size()}, {"uri", "data:,"}}}};
    for (auto& [id, view] : binary["bufferViews"].items()) view["buffer"] = "binary_glTF";
    const std::string content = binary.dump();
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67), u32(1), u32(static_cast<uint32_t>(20 + content.size() + bin.size()));
    u32(static_cast<uint32_t>(content.size())), u32(0);
    return out + content + bin;
  }
};

void expect_translated_sphere(const PolygonMesh& read, const PolygonMesh& sphere) {
  ASSERT_EQ(read.vertex_count(), sphere.vertex_count());
  for (size_t v = 0; v < sphere.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(read.positions[v][k], sphere.positions[v][k] + (k == 0 ? 10 : 0), 1e-6) << v;
  EXPECT_EQ(read.indices, sphere.indices);
  EXPECT_EQ(read.face_count(), sphere.face_count());
}

TEST(Gltf1, ReadsInterleavedAccessorsAndNodeTransformsAsStored) {
  const Gltf1Sphere sphere;
  GltfReadStats stats;
  expect_translated_sphere(read_gltf(as_bytes(sphere.text()), {}, &stats), sphere.mesh);
  ASSERT_FALSE(stats.warnings.empty());
  EXPECT_NE(stats.warnings[0].find("read as glTF 1.0"), std::string::npos);
}

TEST(Gltf1, ReadsTheGlb1ContainerFromItsBinaryBody) {
  const Gltf1Sphere sphere;
  expect_translated_sphere(read_gltf(as_bytes(sphere.glb())), sphere.mesh);
}

// A 1.0 node may draw several meshes; 2.0's one-mesh nodes get a child per mesh.
TEST(Gltf1, ANodeOfTwoMeshesDrawsBoth) {
  Gltf1Sphere sphere;
  sphere.document["meshes"]["sphere_again"] = sphere.document["meshes"]["sphere"];
  sphere.document["nodes"]["child"]["meshes"] = {"sphere", "sphere_again"};
  const PolygonMesh read = read_gltf(as_bytes(sphere.text()));
  EXPECT_EQ(read.face_count(), 2 * sphere.mesh.face_count());
  EXPECT_EQ(read.vertex_count(), 2 * sphere.mesh.vertex_count());
}

TEST(Gltf1, KeepsTheDiffuseColourOrTextureAsBaseColour) {
  Gltf1Sphere sphere;
  GltfAppearance look;
  read_gltf(as_bytes(sphere.text()), {}, nullptr, nullptr, &look);
  ASSERT_EQ(look.materials.size(), 1u);
  // 1.5 clamped to 1, the missing alpha 1.
  EXPECT_EQ(look.materials[0]["pbrMetallicRoughness"]["baseColorFactor"],
            json::array({1.0, 0.0, 0.0, 1.0}));
  // Without KHR_materials_common the technique's own values are read: a texture here.
  sphere.document["materials"]["red"] = {{"values", {{"diffuse", "logo"}}}};
  sphere.document["textures"] = {{"logo", {{"source", "logo_image"}, {"sampler", "linear"}}}};
  sphere.document["images"] = {{"logo_image", {{"uri", "logo.png"}}}};
  sphere.document["samplers"] = {{"linear", {{"magFilter", 9729}}}};
  GltfAppearance textured;
  read_gltf(as_bytes(sphere.text()), {}, nullptr, nullptr, &textured);
  ASSERT_EQ(textured.materials.size(), 1u);
  EXPECT_EQ(textured.materials[0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
  EXPECT_EQ(textured.textures[0]["source"], 0);
  EXPECT_EQ(textured.samplers[0]["magFilter"], 9729);
}

// A material that gives no diffuse of its own has its technique's default (COLLADA2GLTF
// writes constant colours there); a malformed technique is ignored, as techniques are.
TEST(Gltf1, AMaterialWithoutADiffuseTakesItsTechniquesDefault) {
  Gltf1Sphere sphere;
  sphere.document["materials"]["red"] = {{"technique", "lambert"}, {"values", json::object()}};
  sphere.document["techniques"] = {
      {"lambert",
       {{"parameters", {{"diffuse", {{"type", 35666}, {"value", {0.0, 0.5, 1.0, 1.0}}}}}}}}};
  GltfAppearance look;
  read_gltf(as_bytes(sphere.text()), {}, nullptr, nullptr, &look);
  ASSERT_EQ(look.materials.size(), 1u);
  EXPECT_EQ(look.materials[0]["pbrMetallicRoughness"]["baseColorFactor"],
            json::array({0.0, 0.5, 1.0, 1.0}));
  sphere.document["techniques"]["lambert"]["parameters"] = "not an object";
  GltfAppearance plain;
  read_gltf(as_bytes(sphere.text()), {}, nullptr, nullptr, &plain);
  ASSERT_EQ(plain.materials.size(), 1u);
  EXPECT_FALSE(plain.materials[0]["pbrMetallicRoughness"].contains("baseColorFactor"));
}

TEST(Gltf1, NamesTheIdsAndContainersItCannotRead) {
  Gltf1Sphere missing;
  missing.document["meshes"]["sphere"]["primitives"][0]["attributes"]["POSITION"] = "nowhere";
  EXPECT_NE(read_error(missing.text())
                .find("glTF 1.0: mesh \"sphere\" primitive 0's POSITION refers to accessor "
                      "\"nowhere\", which the file does not have"),
            std::string::npos);
  Gltf1Sphere quantized;
  quantized.document["accessors"]["position"]["extensions"] = {
      {"WEB3D_quantized_attributes", {{"decodeMatrix", json::array()}}}};
  EXPECT_NE(read_error(quantized.text()).find("WEB3D_quantized_attributes"), std::string::npos);
  Gltf1Sphere past;
  past.document["accessors"]["normal"]["byteOffset"] = 100000;
  EXPECT_NE(read_error(past.text()).find("accessor \"normal\"'s byteOffset 100000 is past the end"),
            std::string::npos);
  Gltf1Sphere listed;
  listed.document["nodes"] = json::array();  // 2.0's shape in a 1.0 file
  EXPECT_NE(read_error(listed.text()).find("nodes is not an object"), std::string::npos);

  const Gltf1Sphere sphere;
  std::string long_content = sphere.glb();
  const uint32_t too_long = static_cast<uint32_t>(long_content.size());
  std::memcpy(long_content.data() + 12, &too_long, 4);
  EXPECT_NE(read_error(long_content).find("GLB 1.0 declares"), std::string::npos);
  std::string not_json = sphere.glb();
  const uint32_t format = 1;
  std::memcpy(not_json.data() + 16, &format, 4);
  EXPECT_NE(read_error(not_json).find("content format 1 is not JSON"), std::string::npos);
  // The body is the binary_glTF buffer: a .gltf 1.0 JSON naming it has no bytes for it.
  const std::string glb = sphere.glb();
  json loose = json::parse(glb.substr(20, glb.size() - 20 - sphere.bin.size()));
  loose["buffers"]["binary_glTF"].erase("uri");
  const std::string no_data = read_error(loose.dump());
  EXPECT_NE(no_data.find("reads buffer 0, which has no data"), std::string::npos) << no_data;
  // An index in a message numbers the upgrade's objects, which the message says.
  EXPECT_NE(no_data.find("numbered in the order of their ids"), std::string::npos) << no_data;
}

}  // namespace
}  // namespace spheremap
