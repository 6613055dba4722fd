// glTF as exporters ship it: a .gltf with its .bin beside it, KHR_mesh_quantization,
// EXT_meshopt_compression, required extensions, instancing, repeated meshes,
// and the Khronos sample models of the corpus (gltf-samples/).
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <tuple>

#include "core/io/gltf_reader.h"
#include "core/io/mesh_file.h"
#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/outputs/report_json.h"
#include "tests/corpus.h"
#include "tests/gltf_files.h"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing::as_bytes;
using testing::Glb;
using testing::read_error;
using testing::sphere_glb;

// A fresh folder under the system temp dir, removed at the end of the test.
struct TempFolder {
  fs::path path;
  TempFolder() {
    static int made = 0;
    path = fs::temp_directory_path() /
           ("spheremap_gltf_" + std::to_string(getpid()) + "_" + std::to_string(++made));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempFolder() { fs::remove_all(path); }
  void write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path / name, std::ios::binary) << bytes;
  }
};

// The test sphere as a .gltf whose buffer is the file `bin_name` named by `uri`.
void write_split_gltf(const TempFolder& folder, const std::string& gltf_name,
                      const std::string& uri, const std::string& bin_name) {
  Glb glb(sphere_glb());
  glb.json["buffers"][0]["uri"] = uri;
  folder.write(gltf_name, glb.json.dump());
  folder.write(bin_name, glb.bin);
}

InputError read_failure(const std::string& bytes, const GltfReadOptions& options = {},
                        const GltfResources* resources = nullptr) {
  try {
    read_gltf(as_bytes(bytes), options, nullptr, resources);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError";
  return InputError("none", "");
}

TEST(GltfRealWorld, ReadsABinBesideTheGltfByItsPercentEncodedUri) {
  TempFolder folder;
  write_split_gltf(folder, "sphere.gltf", "mesh%20data.bin", "mesh data.bin");
  const PolygonMesh expected = read_gltf(as_bytes(sphere_glb()));
  const PolygonMesh read = read_mesh_file((folder.path / "sphere.gltf").string());
  EXPECT_EQ(read.positions, expected.positions);
  EXPECT_EQ(read.indices, expected.indices);
}

TEST(GltfRealWorld, ListsMissingFilesAndSaysWhereTheyMustBe) {
  TempFolder folder;
  write_split_gltf(folder, "sphere.gltf", "elsewhere.bin", "mesh.bin");
  try {
    read_mesh_file((folder.path / "sphere.gltf").string());
    ADD_FAILURE() << "expected missing_resources";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "missing_resources");
    EXPECT_NE(std::string(e.what()).find("\"elsewhere.bin\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the .gltf's folder"), std::string::npos) << e.what();
  }
  // From memory (the service's multipart parts): found by name, or told how to send it.
  Glb glb(sphere_glb());
  glb.json["buffers"][0]["uri"] = "a.bin";
  const MemoryResources parts({{"a.bin", glb.bin}}, "send it as a part");
  EXPECT_EQ(read_gltf(as_bytes(glb.json.dump()), {}, nullptr, &parts).positions.size(), 42u);
  const MemoryResources none({}, "send it as a part");
  const InputError e = read_failure(glb.json.dump(), {}, &none);
  EXPECT_EQ(e.check(), "missing_resources");
  EXPECT_NE(std::string(e.what()).find("send it as a part"), std::string::npos);
}

TEST(GltfRealWorld, RefusesSymlinksLeadingOutOfTheFolder) {
  TempFolder outside, folder;
  Glb glb(sphere_glb());
  outside.write("secret.bin", glb.bin);
  fs::create_symlink(outside.path / "secret.bin", folder.path / "link.bin");
  glb.json["buffers"][0]["uri"] = "link.bin";
  folder.write("a.gltf", glb.json.dump());
  try {
    read_mesh_file((folder.path / "a.gltf").string());
    ADD_FAILURE() << "a symlink out of the folder was followed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("symbolic link"), std::string::npos) << e.what();
  }
  // A link that stays inside the folder is fine.
  folder.write("real.bin", glb.bin);
  fs::create_symlink(folder.path / "real.bin", folder.path / "inside.bin");
  glb.json["buffers"][0]["uri"] = "inside.bin";
  folder.write("b.gltf", glb.json.dump());
  EXPECT_EQ(read_mesh_file((folder.path / "b.gltf").string()).positions.size(), 42u);
}

TEST(GltfRealWorld, ChecksRequiredExtensionsByName) {
  Glb glb(sphere_glb());
  glb.json["extensionsRequired"] = {"KHR_materials_unlit", "EXT_made_up_geometry"};
  EXPECT_NE(read_error(glb.bytes()).find("\"EXT_made_up_geometry\""), std::string::npos);
  glb.json["extensionsRequired"] = {"KHR_materials_unlit", "KHR_texture_transform"};
  EXPECT_EQ(read_gltf(as_bytes(glb.bytes())).positions.size(), 42u);
}

// KHR_techniques_webgl (custom shaders) is read as stored, with a warning that its shaders
// are not run; without it there is no warning.
TEST(GltfRealWorld, ReadsShaderTechniquesAsStoredWithAWarning) {
  Glb glb(sphere_glb());
  glb.json["extensionsUsed"] = glb.json["extensionsRequired"] = {"KHR_techniques_webgl"};
  GltfReadStats stats;
  EXPECT_EQ(read_gltf(as_bytes(glb.bytes()), {}, &stats).positions,
            read_gltf(as_bytes(sphere_glb())).positions);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_EQ(stats.warnings[0],
            "the file's KHR_techniques_webgl shaders are not run: its geometry is read as stored");
  GltfReadStats plain;
  read_gltf(as_bytes(sphere_glb()), {}, &plain);
  EXPECT_TRUE(plain.warnings.empty());
}

// A glTF 2.0 GLB whose header says version 1 is read as GLB 1.0 (gltf1_test.cpp), whose
// header has a content format where 2.0 has its chunk type: refused, saying so.
TEST(GltfRealWorld, AGlb2HeaderSayingVersion1IsReadAsGlb1AndRefused) {
  std::string glb = sphere_glb();
  const uint32_t version1 = 1;
  std::memcpy(glb.data() + 4, &version1, 4);
  const std::string message = read_error(glb);
  EXPECT_NE(message.find("GLB 1.0 content format 1313821514 is not JSON (0)"), std::string::npos)
      << message;
}

// The test sphere with positions stored as `component_type` (BYTE .. UNSIGNED_SHORT)
// quantized over [-1, 1] (normalized) or [0, max] with a node transform undoing it.
std::string quantized_sphere(int component_type, bool normalized, bool declare_extension) {
  Glb glb(sphere_glb());
  const PolygonMesh m = read_gltf(as_bytes(sphere_glb()));
  const bool is_signed = component_type == 5120 || component_type == 5122;
  const size_t size = component_type <= 5121 ? 1 : 2;
  const double max = size == 1 ? (is_signed ? 127 : 255) : (is_signed ? 32767 : 65535);
  std::string positions;
  for (const Vec3& p : m.positions) {
    for (int c = 0; c < 3; ++c) {
      // Unsigned: shift [-1, 1] to [0, 1]; the node's translation moves it back.
      const double unit = is_signed ? p[c] : (p[c] + 1) / 2;
      const int q = static_cast<int>(std::lround(unit * max));
      positions.append(reinterpret_cast<const char*>(&q), size);
    }
    while (positions.size() % 4) positions.push_back('\0');  // 4-byte aligned stride
  }
  const size_t stride = positions.size() / m.positions.size();
  const size_t offset = glb.bin.size();
  glb.bin += positions;
  glb.json["buffers"][0]["byteLength"] = glb.bin.size();
  glb.json["bufferViews"].push_back({{"buffer", 0},
                                     {"byteOffset", offset},
                                     {"byteLength", positions.size()},
                                     {"byteStride", stride}});
  const int position = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  auto& accessor = glb.json["accessors"][position];
  accessor["bufferView"] = glb.json["bufferViews"].size() - 1;
  accessor["byteOffset"] = 0;
  accessor["componentType"] = component_type;
  accessor.erase("min"), accessor.erase("max");
  if (normalized) accessor["normalized"] = true;
  const double scale = normalized ? (is_signed ? 1.0 : 2.0) : (is_signed ? 1 / max : 2 / max);
  glb.json["nodes"][0]["scale"] = {scale, scale, scale};
  if (!is_signed) glb.json["nodes"][0]["translation"] = {-1.0, -1.0, -1.0};
  if (declare_extension) {
    glb.json["extensionsUsed"] = {"KHR_mesh_quantization"};
    glb.json["extensionsRequired"] = {"KHR_mesh_quantization"};
  }
  return glb.bytes();
}

TEST(GltfRealWorld, ReadsKhrMeshQuantizationInEveryIntegerType) {
  const PolygonMesh expected = read_gltf(as_bytes(sphere_glb()));
  for (int type : {5120, 5121, 5122, 5123})
    for (bool normalized : {false, true}) {
      const PolygonMesh m = read_gltf(as_bytes(quantized_sphere(type, normalized, true)));
      ASSERT_EQ(m.positions.size(), expected.positions.size());
      const double step = type <= 5121 ? 2.0 / 127 : 2.0 / 32767;
      double worst = 0;
      for (size_t v = 0; v < m.positions.size(); ++v)
        worst = std::max(worst, norm(m.positions[v] - expected.positions[v]));
      EXPECT_LT(worst, step) << "componentType " << type << " normalized " << normalized;
      EXPECT_EQ(m.indices, expected.indices);
    }
  const std::string message = read_error(quantized_sphere(5122, true, false));
  EXPECT_NE(message.find("KHR_mesh_quantization"), std::string::npos) << message;
}

// The test sphere with both views meshopt-encoded (by meshoptimizer's own encoder) under
// `extension` (EXT_ or KHR_meshopt_compression), the uncompressed buffer a fallback
// placeholder with no data.
std::string meshopt_sphere(const char* extension = "EXT_meshopt_compression") {
  const PolygonMesh m = read_gltf(as_bytes(sphere_glb()));
  std::vector<float> vertices;
  for (const Vec3& p : m.positions)
    for (int c = 0; c < 3; ++c) vertices.push_back(static_cast<float>(p[c]));
  const size_t count = m.positions.size(), index_count = m.indices.size();
  std::vector<unsigned char> encoded_vertices(meshopt_encodeVertexBufferBound(count, 12));
  encoded_vertices.resize(meshopt_encodeVertexBuffer(
      encoded_vertices.data(), encoded_vertices.size(), vertices.data(), count, 12));
  std::vector<unsigned char> encoded_indices(meshopt_encodeIndexBufferBound(index_count, count));
  encoded_indices.resize(meshopt_encodeIndexBuffer(encoded_indices.data(), encoded_indices.size(),
                                                   m.indices.data(), index_count));
  Glb glb(sphere_glb());
  glb.bin.assign(encoded_vertices.begin(), encoded_vertices.end());
  while (glb.bin.size() % 4) glb.bin.push_back('\0');
  const size_t index_offset = glb.bin.size();
  glb.bin.append(encoded_indices.begin(), encoded_indices.end());
  while (glb.bin.size() % 4) glb.bin.push_back('\0');
  using nlohmann::json;
  glb.json["buffers"] = json::array({{{"byteLength", glb.bin.size()}},
                                     {{"byteLength", count * 12 + index_count * 4},
                                      {"extensions", {{extension, {{"fallback", true}}}}}}});
  auto view = [extension](size_t offset, size_t length, size_t stride, size_t n, const char* mode,
                          size_t decoded_offset) {
    return json{{"buffer", 1},
                {"byteOffset", decoded_offset},
                {"byteLength", n * stride},
                {"extensions",
                 {{extension,
                   {{"buffer", 0},
                    {"byteOffset", offset},
                    {"byteLength", length},
                    {"byteStride", stride},
                    {"count", n},
                    {"mode", mode}}}}}};
  };
  glb.json["bufferViews"] = json::array(
      {view(0, encoded_vertices.size(), 12, count, "ATTRIBUTES", 0),
       view(index_offset, encoded_indices.size(), 4, index_count, "TRIANGLES", count * 12)});
  glb.json["accessors"] = json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}},
       {{"bufferView", 1}, {"componentType", 5125}, {"count", index_count}, {"type", "SCALAR"}}});
  glb.json["meshes"][0]["primitives"] =
      json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}});
  glb.json["extensionsUsed"] = glb.json["extensionsRequired"] = {extension};
  return glb.bytes();
}

// Each triangle's corners rotated to its smallest (the index codec may rotate them, keeping
// the winding).
std::vector<uint32_t> rotated_to_smallest(std::vector<uint32_t> indices) {
  for (size_t t = 0; t + 2 < indices.size(); t += 3)
    while (indices[t] > indices[t + 1] || indices[t] > indices[t + 2])
      std::rotate(indices.begin() + t, indices.begin() + t + 1, indices.begin() + t + 3);
  return indices;
}

TEST(GltfRealWorld, ReadsExtAndKhrMeshoptCompressionExactly) {
  const PolygonMesh expected = read_gltf(as_bytes(sphere_glb()));
  for (const char* extension : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    const PolygonMesh m = read_gltf(as_bytes(meshopt_sphere(extension)));
    EXPECT_EQ(m.positions, expected.positions) << extension;  // float32 in both: bit-exact
    EXPECT_EQ(rotated_to_smallest(m.indices), rotated_to_smallest(expected.indices)) << extension;
  }
}

// What KHR_meshopt_compression adds over EXT and Debian's meshoptimizer 0.18 cannot decode
// (version 1 of the vertex codec, the COLOR filter) is refused by name, not as a corrupt stream.
TEST(GltfRealWorld, KhrMeshoptFeaturesThisMeshoptimizerLacksAreNamed) {
  Glb version1(meshopt_sphere("KHR_meshopt_compression"));
  ASSERT_EQ(static_cast<uint8_t>(version1.bin[0]), 0xa0);  // the vertex codec's header
  version1.bin[0] = '\xa1';
  const std::string v1 = read_error(version1.bytes());
  EXPECT_NE(v1.find("bufferView 0 (KHR_meshopt_compression) is encoded with version 1 of "
                    "meshoptimizer's vertex codec"),
            std::string::npos)
      << v1;
  Glb wide(meshopt_sphere("KHR_meshopt_compression"));
  wide.json["bufferViews"][0]["extensions"]["KHR_meshopt_compression"]["byteStride"] = 300;
  EXPECT_NE(read_error(wide.bytes())
                .find("bufferView 0 (KHR_meshopt_compression)'s byteStride 300 is not an integer "
                      "from 1 to 256"),
            std::string::npos);
  Glb color(meshopt_sphere("KHR_meshopt_compression"));
  color.json["bufferViews"][0]["extensions"]["KHR_meshopt_compression"]["filter"] = "COLOR";
  const std::string filter = read_error(color.bytes());
  EXPECT_NE(filter.find("uses the COLOR filter"), std::string::npos) << filter;
}

TEST(GltfRealWorld, RefusesMeshoptStreamsThatDoNotDecodeOrClaimTooMuch) {
  Glb corrupt(meshopt_sphere());
  std::fill(corrupt.bin.begin(), corrupt.bin.begin() + 8, '\xff');
  EXPECT_NE(read_error(corrupt.bytes()).find("does not decode"), std::string::npos);
  Glb huge(meshopt_sphere());  // 4 billion vertices from a few hundred bytes
  huge.json["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 4000000000u;
  try {
    read_gltf(as_bytes(huge.bytes()));
    ADD_FAILURE() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_TRUE(e.check() == "too_large" || e.check() == "gltf") << e.check();
    EXPECT_NE(std::string(e.what()).find("bufferView 0"), std::string::npos) << e.what();
  }
  Glb placeholder(meshopt_sphere());  // a plain view reading the placeholder buffer
  placeholder.json["bufferViews"][0].erase("extensions");
  EXPECT_NE(read_error(placeholder.bytes()).find("stands in for meshopt-compressed data"),
            std::string::npos);
}

// EXT_mesh_gpu_instancing: each instance a copy in world space (the node's transform, then
// the instance's translation, rotation and scale), told as the mesh drawn that many times;
// `mesh` still reads the mesh once.
TEST(GltfRealWorld, GpuInstancesAreReadAsCopiesInWorldSpace) {
  Glb glb(sphere_glb());
  const PolygonMesh sphere = read_gltf(as_bytes(sphere_glb()));
  const float translation[9] = {10, 0, 0, 0, 20, 0, 0, 0, 30};
  const float rotation[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0};  // the third: 180° about z
  const float scale[9] = {1, 1, 1, 2, 2, 2, -1, 1, 1};              // the third mirrors x
  const size_t views = glb.json["bufferViews"].size(), accessors = glb.json["accessors"].size();
  for (const auto& [data, bytes, type] :
       {std::tuple<const float*, size_t, const char*>{translation, sizeof translation, "VEC3"},
        {rotation, sizeof rotation, "VEC4"},
        {scale, sizeof scale, "VEC3"}}) {
    glb.json["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", glb.bin.size()}, {"byteLength", bytes}});
    glb.json["accessors"].push_back({{"bufferView", glb.json["bufferViews"].size() - 1},
                                     {"componentType", 5126},
                                     {"count", 3},
                                     {"type", type}});
    glb.bin.append(reinterpret_cast<const char*>(data), bytes);
  }
  glb.json["buffers"][0]["byteLength"] = glb.bin.size();
  glb.json["nodes"][0]["translation"] = {0, 0, 100};
  glb.json["nodes"][0]["extensions"] = {
      {"EXT_mesh_gpu_instancing",
       {{"attributes",
         {{"TRANSLATION", accessors}, {"ROTATION", accessors + 1}, {"SCALE", accessors + 2}}}}}};
  glb.json["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  ASSERT_EQ(views + 3, glb.json["bufferViews"].size());
  GltfReadStats stats;
  GltfAppearance look;
  const PolygonMesh copies = read_gltf(as_bytes(glb.bytes()), {}, &stats, nullptr, &look);
  const size_t n = sphere.vertex_count();
  ASSERT_EQ(copies.vertex_count(), 3 * n);
  ASSERT_EQ(copies.face_count(), 3 * sphere.face_count());
  for (size_t v = 0; v < n; ++v) {
    const Vec3 p = sphere.positions[v];
    EXPECT_LT(norm(copies.positions[v] - (p + Vec3{10, 0, 100})), 1e-6);
    EXPECT_LT(norm(copies.positions[n + v] - (2 * p + Vec3{0, 20, 100})), 1e-6);
    // Mirrored by the scale, then turned half about z.
    EXPECT_LT(norm(copies.positions[2 * n + v] - (Vec3{p.x, -p.y, p.z} + Vec3{0, 0, 130})), 1e-6);
  }
  // The mirrored copy's faces are flipped back outward, and written so (no node mirrors them).
  EXPECT_EQ(copies.face(2 * sphere.face_count())[1], sphere.face(0)[2] + 2 * n);
  ASSERT_EQ(look.primitives.size(), 3u);
  for (const auto& p : look.primitives) {
    EXPECT_EQ(p.node, -1);
    EXPECT_FALSE(p.mirrored);
  }
  EXPECT_EQ(stats.repeated_mesh, 0);
  EXPECT_EQ(stats.repeated_mesh_draws, 3u);
  GltfReadOptions one;
  one.mesh_index = 0;
  EXPECT_EQ(read_gltf(as_bytes(glb.bytes()), one).positions.size(), n);
  // Instances past the vertex cap are refused before any is read.
  GltfReadOptions capped;
  capped.max_vertices = 2 * n;
  const InputError e = read_failure(glb.bytes(), capped);
  EXPECT_EQ(e.check(), "too_large");
  EXPECT_NE(std::string(e.what()).find("draws mesh 0 3 times, 42 vertices each"), std::string::npos)
      << e.what();
  // More than 2,048 instances in all (here 2,049, of zeros: an accessor without a bufferView)
  // are refused, with the fix of mapping the mesh once.
  Glb many(sphere_glb());
  many.json["accessors"].push_back({{"componentType", 5126}, {"count", 2049}, {"type", "VEC3"}});
  many.json["nodes"][0]["extensions"] = {
      {"EXT_mesh_gpu_instancing",
       {{"attributes", {{"TRANSLATION", many.json["accessors"].size() - 1}}}}}};
  const InputError refused = read_failure(many.bytes());
  EXPECT_EQ(refused.check(), "instancing");
  EXPECT_NE(std::string(refused.what()).find("as 2049 instances; spheremap reads at most 2048"),
            std::string::npos)
      << refused.what();
  EXPECT_EQ(refused.fix().option, "mesh");
  EXPECT_EQ(refused.fix().value, "0");
}

TEST(GltfRealWorld, ASceneDrawingOneMeshTwiceIsToldToPickIt) {
  Glb glb(sphere_glb());
  glb.json["nodes"].push_back(glb.json["nodes"][0]);
  glb.json["scenes"][0]["nodes"].push_back(glb.json["nodes"].size() - 1);
  GltfReadStats stats;
  const PolygonMesh both = read_gltf(as_bytes(glb.bytes()), {}, &stats);
  EXPECT_EQ(stats.repeated_mesh, 0);
  EXPECT_EQ(stats.repeated_mesh_draws, 2u);
  const auto failures = input_failures(prepare_mesh(both, {}), &stats);
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "non_manifold_edge");
  EXPECT_EQ(failures.front().fix.option, "mesh");
  EXPECT_NE(failures.front().fix.effect.find("draws it 2 times"), std::string::npos);
}

TEST(GltfRealWorld, ASceneOfSeveralMeshesListsThemWhenItCannotMap) {
  Glb glb(sphere_glb());
  glb.json["meshes"][0]["name"] = "body";
  nlohmann::json eye = glb.json["meshes"][0];
  eye["name"] = "eye";
  glb.json["meshes"].push_back(eye);
  glb.json["nodes"].push_back({{"mesh", 1}, {"translation", {5.0, 0.0, 0.0}}});
  glb.json["scenes"][0]["nodes"].push_back(glb.json["nodes"].size() - 1);
  GltfReadStats stats;
  const PolygonMesh both = read_gltf(as_bytes(glb.bytes()), {}, &stats);
  ASSERT_EQ(stats.drawn_meshes.size(), 2u);
  const auto failures = input_failures(prepare_mesh(both, {}), &stats);
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "components");
  EXPECT_EQ(failures.front().fix.option, "largest_component");
  EXPECT_NE(failures.front().message.find("2 meshes"), std::string::npos);
  EXPECT_NE(failures.front().message.find("0 'body' (80 triangles), 1 'eye' (80 triangles)"),
            std::string::npos)
      << failures.front().message;
}

// The Khronos sample models of the corpus, as shipped (gltf-samples/MANIFEST.md).
TEST(GltfRealWorld, SampleBoxWithSpacesMapsFromItsGltfAndBin) {
  const std::string path = "gltf-samples/BoxWithSpaces-glTF/Box With Spaces.gltf";
  SKIP_WITHOUT_CORPUS(path);
  const MappedMesh mapped = map_mesh(read_mesh_file(testing::corpus_path(path)), {}, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

TEST(GltfRealWorld, SampleCesiumManDracoGltfMapsCertifiedInFloat32) {
  const std::string path = "gltf-samples/CesiumMan-glTF-Draco/CesiumMan.gltf";
  SKIP_WITHOUT_CORPUS(path);
  GltfReadStats stats;
  const PolygonMesh input = read_mesh_file(testing::corpus_path(path), {}, &stats);
  EXPECT_GT(stats.draco_primitives, 0u);
  const MappedMesh mapped = map_mesh(input, {}, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified)
      << certify(mapped, mapped.float32_check).detail;
}

TEST(GltfRealWorld, SampleBarramundiFishIsRefusedWithTheOptionThatMapsItsBody) {
  const std::string path = "gltf-samples/BarramundiFish-glTF/BarramundiFish.gltf";
  SKIP_WITHOUT_CORPUS(path);
  const PolygonMesh input = read_mesh_file(testing::corpus_path(path));
  try {
    map_mesh(input, {}, {});
    ADD_FAILURE() << "three parts mapped as one";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "components");
    EXPECT_EQ(e.fix().option, "largest_component");
  }
  PrepareOptions largest;
  largest.largest_component = true;
  const MappedMesh body = map_mesh(input, largest, {});
  EXPECT_TRUE(certify(body, body.float32_check).certified);
}

}  // namespace
}  // namespace spheremap
