// Outputs keep the input's look: materials, textures, images, TEXCOORD_0, names, nodes and
// transforms through sphere.glb and morph.glb, and the base colour resampled onto the
// remesh's grid. On generated textured files (always) and on the duck (corpus).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>

#include "core/io/gltf_reader.h"
#include "core/io/image_reader.h"
#include "core/io/mesh_file.h"
#include "core/io/scene_glb.h"
#include "core/map/certification.h"
#include "core/mesh/input_error.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/sphere_asset.h"
#include "tests/corpus.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using testing::as_bytes;
using testing::Glb;

struct ReadBack {
  PolygonMesh mesh;
  GltfAppearance look;
};

ReadBack read_with_look(const std::string& file) {
  ReadBack out;
  out.mesh = read_gltf(as_bytes(file), {}, nullptr, nullptr, &out.look);
  return out;
}

// The input's look against the output's: same materials, textures, samplers and image
// bytes, the same TEXCOORD_0 values vertex for vertex, the same node names and count.
void expect_same_look(const GltfAppearance& in, const GltfAppearance& out) {
  EXPECT_EQ(out.materials, in.materials);
  EXPECT_EQ(out.textures, in.textures);
  EXPECT_EQ(out.samplers, in.samplers);
  EXPECT_EQ(out.cameras, in.cameras);
  EXPECT_EQ(out.image_data, in.image_data);
  EXPECT_EQ(out.image_source, in.image_source);
  ASSERT_EQ(out.primitives.size(), in.primitives.size());
  for (size_t p = 0; p < in.primitives.size(); ++p) {
    EXPECT_EQ(out.primitives[p].material, in.primitives[p].material);
    EXPECT_EQ(out.primitives[p].mesh_name, in.primitives[p].mesh_name);
  }
  ASSERT_NE(in.attribute("TEXCOORD_0"), nullptr);
  ASSERT_NE(out.attribute("TEXCOORD_0"), nullptr);
  EXPECT_EQ(out.attribute("TEXCOORD_0")->values, in.attribute("TEXCOORD_0")->values);
  ASSERT_EQ(out.nodes.size() >= in.nodes.size(), true);
  for (size_t n = 0; n < in.nodes.size(); ++n)
    EXPECT_EQ(out.nodes[n].value("name", ""), in.nodes[n].value("name", ""));
}

void expect_on_unit_sphere(const PolygonMesh& mesh, double tolerance) {
  size_t off = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) off += std::abs(norm(mesh.positions[v]) - 1) > tolerance;
  EXPECT_EQ(off, 0u) << "face corners off the unit sphere (world space)";
}

// A textured horseshoe under a node hierarchy: a root that scales and moves, a child
// that rotates and (with `mirrored`) mirrors, drawing the mesh.
std::string textured_in_hierarchy(bool mirrored) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["nodes"] = {
      {{"name", "root"}, {"translation", {5, -2, 1}}, {"scale", {3, 3, 3}}, {"children", {1}}},
      {{"name", "part"},
       {"rotation", {0, 0.38268343236, 0, 0.92387953251}},
       {"scale", {mirrored ? -1.0 : 1.0, 2.0, 1.0}},
       {"mesh", 0}}};
  glb.json["scenes"] = {{{"nodes", {0}}, {"name", "test scene"}}};
  glb.json["meshes"][0]["name"] = "horseshoe";
  return glb.bytes();
}

TEST(Appearance, ReadsMaterialsTexcoordsImagesAndNodes) {
  const std::string file = textured_in_hierarchy(false);
  const ReadBack in = read_with_look(file);
  ASSERT_EQ(in.look.primitives.size(), 1u);
  const auto& p = in.look.primitives[0];
  EXPECT_EQ(p.node, 1);
  EXPECT_EQ(p.material, 0);
  EXPECT_EQ(p.mesh_name, "horseshoe");
  EXPECT_EQ(p.vertex_count, in.mesh.vertex_count());
  EXPECT_EQ(p.face_count, in.mesh.face_count());
  EXPECT_FALSE(p.mirrored);
  EXPECT_EQ(in.look.materials.size(), 1u);
  ASSERT_EQ(in.look.image_data.size(), 1u);
  ASSERT_NE(in.look.image_bytes(0), nullptr);
  EXPECT_EQ(in.look.images[0]["mimeType"], "image/png");
  const auto image = decode_image(*in.look.image_bytes(0), 1 << 20);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 16);
  EXPECT_EQ(in.look.nodes.size(), 2u);
  EXPECT_EQ(in.look.scene_nodes, std::vector<size_t>{0});
  EXPECT_EQ(in.look.scene_name, "test scene");
  const auto* uv = in.look.attribute("TEXCOORD_0");
  ASSERT_NE(uv, nullptr);
  EXPECT_EQ(uv->values.size(), 2 * in.mesh.vertex_count());
}

TEST(Appearance, SphereAndMorphKeepTheLookAndTheHierarchy) {
  for (bool mirrored : {false, true}) {
    SCOPED_TRACE(mirrored ? "mirrored node" : "plain node");
    const std::string file = textured_in_hierarchy(mirrored);
    const ReadBack in = read_with_look(file);
    EXPECT_EQ(in.look.primitives[0].mirrored, mirrored);
    const MappedMesh mapped = map_mesh(in.mesh, {}, {});
    const SphereAsset sphere =
        sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look);
    EXPECT_TRUE(sphere.metrics["bijective"].get<bool>()) << sphere.metrics.dump();
    const ReadBack out = read_with_look(sphere.glb);
    expect_same_look(in.look, out.look);
    EXPECT_EQ(out.look.nodes[1].value("scale", nlohmann::json()), in.look.nodes[1]["scale"]);
    // Read as a viewer shows it (node transforms applied): the unit sphere, every face.
    EXPECT_EQ(out.mesh.face_count(), in.mesh.face_count());
    expect_on_unit_sphere(out.mesh, 1e-5);

    const MorphAsset morph = morph_asset(mapped, 4, &in.mesh, &in.look);
    const ReadBack base = read_with_look(morph.glb);
    expect_same_look(in.look, base.look);
    ASSERT_EQ(base.mesh.vertex_count(), in.mesh.vertex_count());
    double worst = 0;
    for (size_t v = 0; v < in.mesh.vertex_count(); ++v)
      worst = std::max(worst, norm(base.mesh.positions[v] - in.mesh.positions[v]));
    EXPECT_LT(worst, 1e-4) << "the morph's base is the input where the scene puts it";
    const Glb parts(morph.glb);
    ASSERT_TRUE(parts.json.contains("animations"));
    EXPECT_EQ(parts.json["animations"][0]["channels"][0]["target"]["node"], 1);
    EXPECT_TRUE(parts.json["meshes"][0]["primitives"][0].contains("targets"));
  }
}

TEST(Appearance, DracoOrWeldedSpheresArePlain) {
  const ReadBack in = read_with_look(testing::textured_glb(testing::horseshoe()));
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  for (const auto& [layout, bits] :
       {std::pair{SphereLayout::kWelded, 0}, std::pair{SphereLayout::kOriginal, 14}}) {
    const Glb glb(sphere_asset(in.mesh, mapped, {}, layout, bits, &in.look).glb);
    EXPECT_FALSE(glb.json.contains("materials"));
  }
}

// Brute force: the spherical triangle of the map holding `point` (no locator).
uint32_t containing_triangle(const MappedMesh& mapped, const std::vector<Triangle>& triangles,
                             const Vec3& point) {
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const Vec3 &a = mapped.map.sphere[triangles[t][0]], &b = mapped.map.sphere[triangles[t][1]],
               &c = mapped.map.sphere[triangles[t][2]];
    if (dot(cross(a, b), point) >= 0 && dot(cross(b, c), point) >= 0 &&
        dot(cross(c, a), point) >= 0)
      return t;
  }
  return UINT32_MAX;
}

TEST(Appearance, BakedBaseColourIsTheMaterialOfTheFaceUnderEachTexel) {
  // Two materials by the side of x each face's centroid is on, faces grouped by material
  // into two primitives (as an exporter writes them).
  PolygonMesh mesh;
  mesh.positions = testing::horseshoe().positions;
  for (const Triangle& t : fan_triangulate(testing::horseshoe()).triangles) mesh.add_face(t);
  std::vector<uint32_t> order(mesh.face_count());
  for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
  auto right = [&](uint32_t f) {
    Vec3 c;
    for (uint32_t v : mesh.face(f)) c += mesh.positions[v];
    return c.x > 0;
  };
  std::stable_partition(order.begin(), order.end(), right);
  PolygonMesh grouped;
  grouped.positions = mesh.positions;
  for (uint32_t f : order) grouped.add_face(mesh.face(f));
  const uint32_t first_left = static_cast<uint32_t>(
      std::find_if(order.begin(), order.end(), [&](uint32_t f) { return !right(f); }) -
      order.begin());
  GltfAppearance look;
  look.materials = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}},
                    {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 1, 1}}}}}};
  const auto n = static_cast<uint32_t>(grouped.vertex_count());
  GltfAppearance::Primitive red, blue;
  red.material = 0, red.vertex_count = n, red.face_count = first_left;
  blue.material = 1, blue.vertex_count = n, blue.first_face = first_left;
  blue.face_count = static_cast<uint32_t>(grouped.face_count()) - first_left;
  look.primitives = {red, blue};

  const MappedMesh mapped = map_mesh(grouped, {}, {});
  const int size = 64;
  const std::vector<Triangle> oriented = oriented_triangles(mapped.prepared.welded.mesh).triangles;
  const auto baked = bake_base_color(grouped, look, mapped, oriented, size, 1);
  ASSERT_TRUE(baked);
  EXPECT_EQ(baked->unlocated_texels, 0u);
  const auto image = decode_image(baked->png, 1 << 20);
  ASSERT_TRUE(image);
  size_t agree = 0, reds = 0;
  for (int row = 0; row < size; ++row)
    for (int column = 0; column < size; ++column) {
      const double u = (column + 0.5) / size, v = (row + 0.5) / size;
      const uint32_t t =
          containing_triangle(mapped, oriented, octahedral_decode({2 * u - 1, 1 - 2 * v}));
      ASSERT_NE(t, UINT32_MAX);
      const bool expect_red = t < first_left;  // welded faces keep the input's order
      const uint8_t* px = &image->rgba[(static_cast<size_t>(row) * size + column) * 4];
      const bool is_red = px[0] == 255 && px[1] == 0 && px[2] == 0;
      const bool is_blue = px[0] == 0 && px[1] == 0 && px[2] == 255;
      agree += expect_red ? is_red : is_blue;
      reds += is_red;
    }
  EXPECT_GE(agree, static_cast<size_t>(0.99 * size * size));  // ties on triangle edges
  EXPECT_GT(reds, 0u);
  EXPECT_LT(reds, static_cast<size_t>(size * size));
}

// The colour bake asks its stop check before each decode and each row: asked to stop,
// it throws InputError("stopped") instead of finishing, within a row's time of being
// asked (here a 2048 x 2048 bake told to stop 20 ms in).
TEST(Appearance, TheColourBakeStopsWhenAsked) {
  const ReadBack in = read_with_look(testing::textured_glb(testing::horseshoe()));
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const std::function<bool()> always = [] { return true; };
  try {
    remesh_asset(mapped, 1024, 1, &in.mesh, &in.look, &always);
    ADD_FAILURE() << "not stopped";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped");
  }
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::milliseconds(20);
  size_t asked = 0;
  std::mutex asked_mutex;
  const std::function<bool()> at_deadline = [&] {
    std::lock_guard lock(asked_mutex);
    ++asked;
    return std::chrono::steady_clock::now() >= deadline;
  };
  const OrientedTriangles oriented = oriented_triangles(mapped.prepared.welded.mesh);
  EXPECT_THROW(bake_base_color(in.mesh, in.look, mapped, oriented.triangles, 2048, 1, &at_deadline),
               InputError);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto whole_start = std::chrono::steady_clock::now();
  ASSERT_TRUE(bake_base_color(in.mesh, in.look, mapped, oriented.triangles, 2048, 1));
  const double whole =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - whole_start).count();
  std::printf(
      "2048^2 colour bake: %.3f s whole, stopped %.3f s after its start (deadline 0.020 s, "
      "asked %zu times)\n",
      whole, seconds, asked);
  EXPECT_GT(asked, 1u);  // asked as it went; how soon it stopped is printed, not asserted
}

TEST(Appearance, RemeshCarriesTheTextureItSamples) {
  const std::string file = testing::textured_glb(testing::horseshoe());
  const ReadBack in = read_with_look(file);
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const RemeshAsset remesh = remesh_asset(mapped, 32, 1, &in.mesh, &in.look);
  ASSERT_TRUE(remesh.metrics.contains("texture"));
  EXPECT_EQ(remesh.metrics["texture"]["images_decoded"], 1);
  const Glb glb(remesh.glb);
  ASSERT_TRUE(glb.json.contains("materials"));
  const auto& view = glb.json["bufferViews"][glb.json["images"][0]["bufferView"].get<size_t>()];
  const auto png = decode_image(
      glb.bin.substr(view["byteOffset"].get<size_t>(), view["byteLength"].get<size_t>()), 1 << 24);
  ASSERT_TRUE(png);
  // Every texel is one of the texture's four colours or a blend along their borders; all
  // four appear (the horseshoe's planar projection spans the whole texture).
  std::map<std::array<int, 3>, size_t> seen;
  for (size_t i = 0; i < png->rgba.size(); i += 4)
    ++seen[{png->rgba[i], png->rgba[i + 1], png->rgba[i + 2]}];
  size_t pure = 0;
  for (const auto& c :
       std::vector<std::array<int, 3>>{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}}) {
    EXPECT_GT(seen[c], 0u);
    pure += seen[c];
  }
  EXPECT_GT(pure, png->rgba.size() / 4 / 2);
}

TEST(Appearance, GltfTextOutputReadsAsTheSameAsset) {
  const std::string file = testing::textured_glb(testing::horseshoe());
  const ReadBack in = read_with_look(file);
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const std::string glb =
      sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look).glb;
  const std::string text = glb_to_gltf(glb);
  EXPECT_EQ(text.front(), '{');
  const ReadBack a = read_with_look(glb), b = read_with_look(text);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.mesh.indices, b.mesh.indices);
  EXPECT_EQ(a.look.image_data, b.look.image_data);
  EXPECT_EQ(a.look.image_source, b.look.image_source);
  EXPECT_THROW(glb_to_gltf("not a glb"), std::invalid_argument);
}

TEST(Appearance, BrokenTextureReferencesDropTheMaterialsNotTheMap) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 7;
  const ReadBack in = read_with_look(glb.bytes());
  EXPECT_TRUE(in.look.materials.empty());
  EXPECT_EQ(in.look.primitives[0].material, -1);
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const std::string sphere =
      sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look).glb;
  EXPECT_FALSE(Glb(sphere).json.contains("materials"));
  EXPECT_NE(Glb(sphere).json["meshes"][0]["primitives"][0]["attributes"].count("TEXCOORD_0"), 0u);
}

// The look is the input's JSON: wrong types and broken attribute accessors cost the look
// (or part of it), never the map or an output.
TEST(Appearance, HostileLookValuesAreIgnored) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["samplers"] = {{{"wrapS", "repeat"}, {"wrapT", -3}}};
  glb.json["textures"][0]["sampler"] = 0;
  glb.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = "zero";
  glb.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = 999;
  glb.json["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = "x";
  const ReadBack in = read_with_look(glb.bytes());
  EXPECT_EQ(in.look.attribute("TEXCOORD_1"), nullptr);
  EXPECT_EQ(in.look.attribute("COLOR_0"), nullptr);
  EXPECT_EQ(in.look.samplers[0], nlohmann::json::object());  // only values glTF allows
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const RemeshAsset remesh = remesh_asset(mapped, 16, 1, &in.mesh, &in.look);
  EXPECT_TRUE(remesh.metrics.contains("texture"));
  const MorphAsset morph = morph_asset(mapped, 4, &in.mesh, &in.look);
  EXPECT_EQ(read_with_look(morph.glb).look.materials, in.look.materials);
}

// Node and material members the input got wrong are not copied into outputs (each made
// every output an invalid glTF): a name that is not a string, a rotation that is not a
// unit quaternion (normalized, as the reader applies it), a matrix beside TRS, factors
// out of range, an unknown alpha mode, extensions we do not declare.
TEST(Appearance, InvalidNodeAndMaterialMembersAreNotCopied) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["nodes"] = {
      {{"name", 42}, {"translation", {5, -2, 1}}, {"scale", {3, 3, 3}}, {"children", {1}}},
      {{"name", "part"},
       {"rotation", {0, 0.76536686472, 0, 1.84775906502}},  // twice a unit quaternion
       {"mesh", 0}}};
  glb.json["scenes"] = {{{"nodes", {0}}}};
  nlohmann::json& material = glb.json["materials"][0];
  material["name"] = 5;
  material["pbrMetallicRoughness"]["metallicFactor"] = 7;
  material["pbrMetallicRoughness"]["roughnessFactor"] = 0.5;
  material["pbrMetallicRoughness"]["baseColorFactor"] = {2, 0, 0, 1};
  material["alphaMode"] = "SOMETIMES";
  material["doubleSided"] = "yes";
  material["emissiveFactor"] = {0.5, 0.5, 0.5};
  material["extensions"] = {{"FOO_unknown", {{"x", 1}}},
                            {"KHR_materials_unlit", nlohmann::json::object()}};
  glb.json["extensionsUsed"] = {"KHR_materials_unlit", "FOO_unknown"};
  const ReadBack in = read_with_look(glb.bytes());
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  for (const std::string& file :
       {sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look).glb,
        morph_asset(mapped, 4, &in.mesh, &in.look).glb}) {
    const Glb out(file);
    const nlohmann::json& nodes = out.json["nodes"];
    EXPECT_FALSE(nodes[0].contains("name")) << nodes.dump();
    EXPECT_EQ(nodes[1]["name"], "part");
    const auto q = nodes[1]["rotation"].get<std::vector<double>>();
    ASSERT_EQ(q.size(), 4u);
    EXPECT_NEAR(std::hypot(q[0], q[1], q[2]) * std::hypot(q[0], q[1], q[2]) + q[3] * q[3], 1, 1e-9);
    const nlohmann::json& m = out.json["materials"][0];
    EXPECT_FALSE(m.contains("name")) << m.dump();
    EXPECT_FALSE(m["pbrMetallicRoughness"].contains("metallicFactor")) << m.dump();
    EXPECT_FALSE(m["pbrMetallicRoughness"].contains("baseColorFactor")) << m.dump();
    EXPECT_EQ(m["pbrMetallicRoughness"]["roughnessFactor"], 0.5);
    EXPECT_TRUE(m["pbrMetallicRoughness"].contains("baseColorTexture"));
    EXPECT_FALSE(m.contains("alphaMode"));
    EXPECT_FALSE(m.contains("doubleSided"));
    EXPECT_EQ(m["emissiveFactor"], nlohmann::json({0.5, 0.5, 0.5}));
    EXPECT_FALSE(m["extensions"].contains("FOO_unknown")) << m.dump();
    EXPECT_TRUE(m["extensions"].contains("KHR_materials_unlit")) << m.dump();
    // The geometry agrees with the normalized rotation: a viewer sees the unit sphere.
    if (!out.json.contains("animations"))  // the sphere (the morph's base is the input)
      expect_on_unit_sphere(read_with_look(file).mesh, 1e-5);
  }
}

// A matrix is what the reader applies: TRS beside it is dropped (glTF allows only one).
TEST(Appearance, AMatrixNodeKeepsOnlyItsMatrix) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["nodes"] = {{{"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1}},
                        {"translation", {9, 9, 9}},
                        {"mesh", 0}}};
  glb.json["scenes"] = {{{"nodes", {0}}}};
  const ReadBack in = read_with_look(glb.bytes());
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const std::string sphere =
      sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look).glb;
  const Glb out(sphere);
  const nlohmann::json& node = out.json["nodes"][0];
  EXPECT_TRUE(node.contains("matrix")) << node.dump();
  EXPECT_FALSE(node.contains("translation")) << node.dump();
  expect_on_unit_sphere(read_with_look(sphere).mesh, 1e-5);
}

TEST(Appearance, MissingImageBecomesAPlaceholder) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  glb.json["images"][0].erase("bufferView");
  glb.json["images"][0]["uri"] = "texture.png";  // not supplied
  const ReadBack in = read_with_look(glb.bytes());
  ASSERT_EQ(in.look.images.size(), 1u);
  EXPECT_EQ(in.look.image_bytes(0), nullptr);
  const MappedMesh mapped = map_mesh(in.mesh, {}, {});
  const ReadBack out =
      read_with_look(sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look).glb);
  ASSERT_NE(out.look.image_bytes(0), nullptr);
  const auto placeholder = decode_image(*out.look.image_bytes(0), 16);
  ASSERT_TRUE(placeholder);
  EXPECT_EQ(placeholder->width, 1);
}

TEST(AppearanceCorpus, DuckKeepsItsTextureOnSphereMorphAndRemesh) {
  SKIP_WITHOUT_CORPUS("duck.glb");
  for (const char* name : {"duck.glb", "duck.draco.glb"}) {
    SCOPED_TRACE(name);
    GltfAppearance look;
    const PolygonMesh input = read_mesh_file(testing::corpus_path(name), {}, nullptr, &look);
    ASSERT_EQ(look.primitives.size(), 1u);
    EXPECT_EQ(look.nodes.size(), 3u);  // root (scale 0.01), camera, mesh
    const MappedMesh mapped = map_mesh(input, {}, {});
    const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0, &look);
    EXPECT_TRUE(sphere.metrics["bijective"].get<bool>());
    const ReadBack out = read_with_look(sphere.glb);
    expect_same_look(look, out.look);
    expect_on_unit_sphere(out.mesh, 1e-5);
    const ReadBack morph = read_with_look(morph_asset(mapped, 4, &input, &look).glb);
    expect_same_look(look, morph.look);

    const RemeshAsset remesh = remesh_asset(mapped, 64, 1, &input, &look);
    const Glb glb(remesh.glb);
    const auto& view = glb.json["bufferViews"][glb.json["images"][0]["bufferView"].get<size_t>()];
    const auto png = decode_image(
        glb.bin.substr(view["byteOffset"].get<size_t>(), view["byteLength"].get<size_t>()),
        1 << 24);
    ASSERT_TRUE(png);
    // The duck is yellow with an orange beak and dark eyes: most texels yellow, some
    // orange, some near black.
    size_t yellow = 0, orange = 0, dark = 0;
    for (size_t i = 0; i < png->rgba.size(); i += 4) {
      const int r = png->rgba[i], g = png->rgba[i + 1], b = png->rgba[i + 2];
      yellow += r > 200 && g > 170 && b < 90;
      orange += r > 200 && g > 60 && g < 160 && b < 60;
      dark += r < 60 && g < 60 && b < 60;
    }
    const size_t texels = png->rgba.size() / 4;
    EXPECT_GT(yellow, texels / 2);
    EXPECT_GT(orange, texels / 100);
    EXPECT_GT(dark, 0u);
  }
}

}  // namespace
}  // namespace spheremap
