#include "core/io/glb_writer.h"

#include "core/io/glb_builder.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace spheremap {
namespace {

void append_bytes(std::string& out, const void* data, size_t size) {
  out.append(static_cast<const char*>(data), size);
}

void append_u32(std::string& out, uint32_t v) {
  append_bytes(out, &v, 4);
}

// Adds a float32 xyz attribute with one value per point; returns its unique id.
uint32_t add_draco_vec3(draco::Mesh& out, draco::GeometryAttribute::Type type,
                        const std::vector<Vec3>& values) {
  draco::GeometryAttribute attribute;
  attribute.Init(type, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  const int id = out.AddAttribute(attribute, true, static_cast<uint32_t>(values.size()));
  for (uint32_t i = 0; i < values.size(); ++i) {
    const float f[3] = {static_cast<float>(values[i].x), static_cast<float>(values[i].y),
                        static_cast<float>(values[i].z)};
    out.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), f);
  }
  return out.attribute(id)->unique_id();
}

// The Draco stream of the mesh and the ids of its attributes.
std::string encode_draco(const GlbMesh& mesh, nlohmann::json& attribute_ids) {
  draco::Mesh out;
  out.set_num_points(static_cast<uint32_t>(mesh.positions.size()));
  attribute_ids["POSITION"] =
      add_draco_vec3(out, draco::GeometryAttribute::POSITION, mesh.positions);
  if (!mesh.normals.empty())
    attribute_ids["NORMAL"] = add_draco_vec3(out, draco::GeometryAttribute::NORMAL, mesh.normals);
  if (!mesh.colors.empty()) {
    std::vector<Vec3> colors;
    for (const auto& c : mesh.colors) colors.push_back({c[0], c[1], c[2]});
    attribute_ids["COLOR_0"] = add_draco_vec3(out, draco::GeometryAttribute::COLOR, colors);
  }
  out.SetNumFaces(mesh.triangles.size());
  for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
    draco::Mesh::Face face;
    for (int c = 0; c < 3; ++c) face[c] = draco::PointIndex(mesh.triangles[f][c]);
    out.SetFace(draco::FaceIndex(f), face);
  }
  draco::Encoder encoder;
  encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, mesh.draco_position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(out, &buffer).ok())
    throw std::runtime_error("Draco could not encode the mesh");
  return std::string(buffer.data(), buffer.size());
}

}  // namespace

namespace {

// The textures of the meshes written so far, so that meshes with the same image share one
// material (parts of one asset carry the same checker).
struct MaterialTable {
  nlohmann::json images = nlohmann::json::array(), textures = nlohmann::json::array(),
                 materials = nlohmann::json::array();
  std::vector<const GlbMesh*> owners;  // the mesh each material was made for

  size_t material_for(GlbBuilder& b, const GlbMesh& mesh) {
    for (size_t m = 0; m < owners.size(); ++m)
      if (owners[m]->base_color_png == mesh.base_color_png &&
          owners[m]->normal_png == mesh.normal_png && materials[m]["name"] == mesh.material_name)
        return m;
    const size_t index = materials.size();
    owners.push_back(&mesh);
    // A texture (image and all) per PNG; the same PNG written twice is one texture.
    auto texture = [&](const std::string& png) {
      for (size_t i = 0; i < pngs.size(); ++i)
        if (*pngs[i] == png) return i;
      pngs.push_back(&png);
      images.push_back({{"bufferView", b.add_view(png)}, {"mimeType", "image/png"}});
      textures.push_back({{"source", images.size() - 1}, {"sampler", 0}});
      return textures.size() - 1;
    };
    nlohmann::json pbr = {{"metallicFactor", 0.0}, {"roughnessFactor", 0.9}};
    if (!mesh.base_color_png.empty())
      pbr["baseColorTexture"] = {{"index", texture(mesh.base_color_png)}};
    nlohmann::json material = {{"name", mesh.material_name}, {"pbrMetallicRoughness", pbr}};
    if (!mesh.normal_png.empty()) material["normalTexture"] = {{"index", texture(mesh.normal_png)}};
    materials.push_back(std::move(material));
    return index;
  }

 private:
  std::vector<const std::string*> pngs;  // per texture, its PNG
};

// One glTF mesh (a single primitive) of `mesh`, its data appended to `b`.
nlohmann::json add_mesh(GlbBuilder& b, MaterialTable& table, const GlbMesh& mesh) {
  const bool draco = mesh.draco_position_bits > 0;
  if (draco &&
      (!mesh.texcoords.empty() || !mesh.morph_positions.empty() || !mesh.base_color_png.empty() ||
       !mesh.normal_png.empty() || !mesh.distances.empty()))
    throw std::invalid_argument(
        "build_glb: Draco output carries positions, normals and colours only");
  const size_t n = mesh.positions.size();
  if (!mesh.normal_png.empty() && (mesh.tangents.size() != n || mesh.texcoords.size() != n))
    throw std::invalid_argument(
        "build_glb: a normal map needs a tangent and a texcoord per vertex");
  if (!mesh.colors.empty() && mesh.colors.size() != n)
    throw std::invalid_argument("build_glb: one colour per vertex");
  if (!mesh.distances.empty() && mesh.distances.size() != n)
    throw std::invalid_argument("build_glb: one distance per vertex");
  GlbBuilder::require_float32_positions(mesh.positions);
  // With Draco, accessors describe the decoded data and have no bufferView.
  auto vec3 = [&](const std::vector<Vec3>& values, bool bounds) {
    return draco ? b.add_accessor(GlbBuilder::vec3_accessor(values, bounds))
                 : b.add_vec3(values, bounds);
  };
  nlohmann::json attributes;
  attributes["POSITION"] = vec3(mesh.positions, true);
  if (!mesh.normals.empty()) attributes["NORMAL"] = vec3(mesh.normals, false);
  if (!mesh.normal_png.empty())
    attributes["TANGENT"] = b.add_floats({mesh.tangents.data()->data(), 4 * n}, 4);
  if (!mesh.texcoords.empty())
    attributes["TEXCOORD_0"] = b.add_floats({mesh.texcoords.data()->data(), 2 * n}, 2);
  if (!mesh.colors.empty())
    attributes["COLOR_0"] =
        draco ? b.add_accessor({{"componentType", 5126}, {"count", n}, {"type", "VEC3"}})
              : b.add_floats({mesh.colors.data()->data(), 3 * n}, 3);
  if (!mesh.distances.empty()) attributes["_DISTANCE"] = b.add_floats(mesh.distances, 1);
  nlohmann::json targets = nlohmann::json::array();
  if (!mesh.morph_positions.empty()) {
    nlohmann::json target;
    target["POSITION"] = b.add_vec3(mesh.morph_positions, true);
    if (!mesh.morph_normals.empty()) target["NORMAL"] = b.add_vec3(mesh.morph_normals, false);
    targets.push_back(target);
  }
  const size_t indices =
      draco
          ? b.add_accessor(
                {{"componentType", 5125}, {"count", 3 * mesh.triangles.size()}, {"type", "SCALAR"}})
          : b.add_indices(mesh.triangles);
  nlohmann::json primitive = {{"attributes", attributes}, {"indices", indices}, {"mode", 4}};
  if (!targets.empty()) primitive["targets"] = targets;
  if (!mesh.base_color_png.empty() || !mesh.normal_png.empty())
    primitive["material"] = table.material_for(b, mesh);
  if (draco) {
    nlohmann::json ids;
    const std::string stream = encode_draco(mesh, ids);
    primitive["extensions"] = {
        {"KHR_draco_mesh_compression", {{"bufferView", b.add_view(stream)}, {"attributes", ids}}}};
  }
  nlohmann::json out = {{"primitives", nlohmann::json::array({primitive})},
                        {"extras", mesh.extras}};
  if (!targets.empty()) out["weights"] = {0.0};
  return out;
}

}  // namespace

GlbParts build_glb(const GlbMesh& mesh) {
  const GlbNode node;
  return build_glb({&mesh, 1}, {&node, 1});
}

GlbParts build_glb(std::span<const GlbMesh> meshes, std::span<const GlbNode> nodes) {
  if (meshes.empty() || meshes.size() != nodes.size())
    throw std::invalid_argument("build_glb: one node per mesh, at least one");
  GlbBuilder b;
  MaterialTable table;
  nlohmann::json mesh_list = nlohmann::json::array(), node_list = nlohmann::json::array(),
                 scene_nodes = nlohmann::json::array(), morphing = nlohmann::json::array();
  bool draco = false;
  double morph_seconds = 0;
  for (size_t k = 0; k < meshes.size(); ++k) {
    const GlbMesh& mesh = meshes[k];
    mesh_list.push_back(add_mesh(b, table, mesh));
    nlohmann::json node = {{"mesh", k}};
    const GlbNode& placement = nodes[k];
    if (!placement.name.empty()) node["name"] = placement.name;
    if (placement.scale != 1) node["scale"] = {placement.scale, placement.scale, placement.scale};
    if (placement.translation != Vec3{})
      node["translation"] = {placement.translation.x, placement.translation.y,
                             placement.translation.z};
    node_list.push_back(node);
    scene_nodes.push_back(k);
    draco = draco || mesh.draco_position_bits > 0;
    if (!mesh.morph_positions.empty() && mesh.morph_seconds > 0) {
      morphing.push_back(k);
      morph_seconds = mesh.morph_seconds;
    }
  }
  nlohmann::json json = {
      {"asset", {{"version", "2.0"}, {"generator", "spheremap"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", scene_nodes}}}},
      {"nodes", node_list},
      {"meshes", mesh_list},
  };
  if (!table.materials.empty()) {
    json["images"] = table.images;
    // Linear magnification, trilinear minification, clamped: the square has no wrap.
    json["samplers"] = {
        {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};
    json["textures"] = table.textures;
    json["materials"] = table.materials;
  }
  // array(), not braces: `= {x}` with x a json is a copy of x under clang (CWG 2137), an
  // array of x under gcc.
  if (!morphing.empty())
    json["animations"] = nlohmann::json::array(
        {morph_animation(b, morph_seconds, morphing.get<std::vector<size_t>>())});
  json["accessors"] = b.accessors();
  json["bufferViews"] = b.views();
  json["buffers"] = {{{"byteLength", b.bin().size()}}};
  if (draco) {
    json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  }
  return {std::move(json), std::move(b.bin())};
}

nlohmann::json morph_animation(GlbBuilder& b, double seconds, const std::vector<size_t>& nodes) {
  const float half = static_cast<float>(seconds / 2);
  const float times[] = {0, half, 2 * half}, weights[] = {0, 1, 0};
  const size_t input = b.add_accessor({{"componentType", 5126},
                                       {"count", 3},
                                       {"type", "SCALAR"},
                                       {"min", {0.0}},
                                       {"max", {2 * half}}},
                                      std::string(reinterpret_cast<const char*>(times), 12));
  const size_t output = b.add_floats(weights, 1, 0);
  nlohmann::json channels = nlohmann::json::array();
  for (size_t node : nodes)
    channels.push_back({{"sampler", 0}, {"target", {{"node", node}, {"path", "weights"}}}});
  return {{"name", "mesh to sphere"},
          {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}},
          {"channels", channels}};
}

std::string serialize_glb(const GlbParts& parts) {
  std::string text = parts.json.dump();
  while (text.size() % 4) text.push_back(' ');
  std::string out;
  out.reserve(28 + text.size() + parts.bin.size());
  append_u32(out, 0x46546C67);
  append_u32(out, 2);
  append_u32(out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + parts.bin.size()));
  append_u32(out, static_cast<uint32_t>(text.size()));
  append_u32(out, 0x4E4F534A);
  out += text;
  append_u32(out, static_cast<uint32_t>(parts.bin.size()));
  append_u32(out, 0x004E4942);
  out += parts.bin;
  return out;
}

std::string base64(std::string_view bytes) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = 0;
    for (size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? static_cast<uint8_t>(bytes[i + k]) : 0u);
    for (size_t k = 0; k < 4; ++k) out.push_back(k <= n ? kDigits[(v >> (18 - 6 * k)) & 63] : '=');
  }
  return out;
}

std::string serialize_gltf(const GlbParts& parts) {
  nlohmann::json json = parts.json;
  if (json.contains("buffers") && !json["buffers"].empty())
    json["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(parts.bin);
  return json.dump() + "\n";
}

std::string glb_to_gltf(std::string_view glb) {
  auto u32 = [&](size_t at) {
    uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  if (glb.size() < 20 || u32(0) != 0x46546C67 || u32(16) != 0x4E4F534A || u32(12) > glb.size() - 20)
    throw std::invalid_argument("not a GLB");
  GlbParts parts;
  const size_t json_end = 20 + u32(12);
  parts.json = nlohmann::json::parse(glb.substr(20, u32(12)));
  if (glb.size() >= json_end + 8 && u32(json_end + 4) == 0x004E4942 &&
      u32(json_end) <= glb.size() - json_end - 8)
    parts.bin = std::string(glb.substr(json_end + 8, u32(json_end)));
  return serialize_gltf(parts);
}

}  // namespace spheremap
