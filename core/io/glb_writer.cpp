#include "core/io/glb_writer.h"

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

// Appends float32 xyz triples; returns {min, max} per axis of what was written.
std::pair<std::array<float, 3>, std::array<float, 3>> append_vec3(std::string& bin,
                                                                  const std::vector<Vec3>& v) {
  std::array<float, 3> lo, hi;
  lo.fill(std::numeric_limits<float>::max());
  hi.fill(std::numeric_limits<float>::lowest());
  for (const Vec3& p : v) {
    const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    append_bytes(bin, f, sizeof f);
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], f[k]), hi[k] = std::max(hi[k], f[k]);
  }
  return {lo, hi};
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

GlbParts build_glb(const GlbMesh& mesh) {
  const bool draco = mesh.draco_position_bits > 0;
  if (draco &&
      (!mesh.texcoords.empty() || !mesh.morph_positions.empty() || !mesh.base_color_png.empty()))
    throw std::invalid_argument("build_glb: Draco output carries positions and normals only");
  const size_t n = mesh.positions.size();
  std::string bin;
  nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
  // With Draco, accessors describe the decoded data and have no bufferView.
  auto add_view = [&](const std::string& data, int target) {
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", data.size()}};
    if (target) view["target"] = target;
    views.push_back(std::move(view));
    bin += data;
    while (bin.size() % 4) bin.push_back('\0');
    return views.size() - 1;
  };
  auto add_accessor = [&](nlohmann::json accessor, const std::string& data, int target) {
    if (!draco) accessor["bufferView"] = add_view(data, target);
    accessors.push_back(std::move(accessor));
    return accessors.size() - 1;
  };
  std::string data;
  const auto [lo, hi] = append_vec3(data, mesh.positions);
  nlohmann::json attributes;
  attributes["POSITION"] = add_accessor(
      {{"componentType", 5126}, {"count", n}, {"type", "VEC3"}, {"min", lo}, {"max", hi}}, data,
      34962);
  if (!mesh.normals.empty()) {
    data.clear();
    append_vec3(data, mesh.normals);
    attributes["NORMAL"] =
        add_accessor({{"componentType", 5126}, {"count", n}, {"type", "VEC3"}}, data, 34962);
  }
  if (!mesh.texcoords.empty()) {
    data.clear();
    for (const auto& uv : mesh.texcoords) append_bytes(data, uv.data(), 8);
    attributes["TEXCOORD_0"] =
        add_accessor({{"componentType", 5126}, {"count", n}, {"type", "VEC2"}}, data, 34962);
  }
  nlohmann::json targets = nlohmann::json::array();
  if (!mesh.morph_positions.empty()) {
    data.clear();
    const auto [dlo, dhi] = append_vec3(data, mesh.morph_positions);
    nlohmann::json target;
    target["POSITION"] = add_accessor(
        {{"componentType", 5126}, {"count", n}, {"type", "VEC3"}, {"min", dlo}, {"max", dhi}}, data,
        34962);
    if (!mesh.morph_normals.empty()) {
      data.clear();
      append_vec3(data, mesh.morph_normals);
      target["NORMAL"] =
          add_accessor({{"componentType", 5126}, {"count", n}, {"type", "VEC3"}}, data, 34962);
    }
    targets.push_back(target);
  }
  data.clear();
  for (const Triangle& t : mesh.triangles) append_bytes(data, t.data(), 12);
  const size_t indices = add_accessor(
      {{"componentType", 5125}, {"count", 3 * mesh.triangles.size()}, {"type", "SCALAR"}}, data,
      34963);
  nlohmann::json primitive = {{"attributes", attributes}, {"indices", indices}, {"mode", 4}};
  if (!targets.empty()) primitive["targets"] = targets;
  nlohmann::json extra_members = nlohmann::json::object();
  if (!mesh.base_color_png.empty()) {
    primitive["material"] = 0;
    extra_members["images"] = {
        {{"bufferView", add_view(mesh.base_color_png, 0)}, {"mimeType", "image/png"}}};
    // Linear magnification, trilinear minification, clamped: the square has no wrap.
    extra_members["samplers"] = {
        {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};
    extra_members["textures"] = {{{"source", 0}, {"sampler", 0}}};
    extra_members["materials"] = {{{"name", "checker"},
                                   {"pbrMetallicRoughness",
                                    {{"baseColorTexture", {{"index", 0}}},
                                     {"metallicFactor", 0.0},
                                     {"roughnessFactor", 0.9}}}}};
  }
  if (!targets.empty() && mesh.morph_seconds > 0) {
    const float half = static_cast<float>(mesh.morph_seconds / 2);
    const float times[] = {0, half, 2 * half}, weights[] = {0, 1, 0};
    std::string time_data, weight_data;
    append_bytes(time_data, times, sizeof times);
    append_bytes(weight_data, weights, sizeof weights);
    const size_t input = add_accessor({{"componentType", 5126},
                                       {"count", 3},
                                       {"type", "SCALAR"},
                                       {"min", {0.0}},
                                       {"max", {2 * half}}},
                                      time_data, 0);
    const size_t output =
        add_accessor({{"componentType", 5126}, {"count", 3}, {"type", "SCALAR"}}, weight_data, 0);
    extra_members["animations"] = {
        {{"name", "mesh to sphere"},
         {"samplers", {{{"input", input}, {"output", output}, {"interpolation", "LINEAR"}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}}};
  }
  if (draco) {
    nlohmann::json ids;
    const std::string stream = encode_draco(mesh, ids);
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", stream.size()}});
    bin += stream;
    primitive["extensions"] = {
        {"KHR_draco_mesh_compression", {{"bufferView", views.size() - 1}, {"attributes", ids}}}};
  }
  while (bin.size() % 4) bin.push_back('\0');
  nlohmann::json json = {
      {"asset", {{"version", "2.0"}, {"generator", "spheremap"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {primitive}}, {"extras", mesh.extras}}}},
      {"accessors", accessors},
      {"bufferViews", views},
      {"buffers", {{{"byteLength", bin.size()}}}},
  };
  for (const auto& [key, value] : extra_members.items()) json[key] = value;
  if (!targets.empty()) json["meshes"][0]["weights"] = {0.0};
  if (draco) {
    json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  }
  return {std::move(json), std::move(bin)};
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

}  // namespace spheremap
