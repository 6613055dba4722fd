#include "core/io/scene_glb.h"

#include <cmath>
#include <map>

#include "core/io/glb_builder.h"
#include "core/io/png_writer.h"

namespace spheremap {
namespace {

// A node's world transform split as p_world = linear * p_local + translation, with the
// inverse of `linear`; `invertible` false when the scene cannot be kept (the primitive is
// then written in world space under a new root node).
struct Frame {
  bool invertible = false;
  double linear[9]{}, inverse[9]{};  // row-major
  Vec3 translation;

  Vec3 point_to_local(const Vec3& p) const { return vector_to_local(p - translation); }
  Vec3 vector_to_local(const Vec3& v) const {
    return {inverse[0] * v.x + inverse[1] * v.y + inverse[2] * v.z,
            inverse[3] * v.x + inverse[4] * v.y + inverse[5] * v.z,
            inverse[6] * v.x + inverse[7] * v.y + inverse[8] * v.z};
  }
  // Normals transform by the inverse transpose, so back by the transpose.
  Vec3 normal_to_local(const Vec3& n) const {
    const Vec3 m = {linear[0] * n.x + linear[3] * n.y + linear[6] * n.z,
                    linear[1] * n.x + linear[4] * n.y + linear[7] * n.z,
                    linear[2] * n.x + linear[5] * n.y + linear[8] * n.z};
    const double length = norm(m);
    return length > 0 ? m * (1 / length) : Vec3{0, 0, 1};
  }
};

Frame identity_frame() {
  Frame f;
  f.invertible = true;
  f.linear[0] = f.linear[4] = f.linear[8] = f.inverse[0] = f.inverse[4] = f.inverse[8] = 1;
  return f;
}

Frame frame_of(const Matrix4& m) {
  Frame f;
  double* a = f.linear;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r * 3 + c] = m[static_cast<size_t>(c * 4 + r)];
  f.translation = {m[12], m[13], m[14]};
  const double det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
                     a[2] * (a[3] * a[7] - a[4] * a[6]);
  double scale = 0;
  for (double x : f.linear) scale = std::max(scale, std::abs(x));
  if (!std::isfinite(det) || !is_finite(f.translation) ||
      std::abs(det) <= 1e-12 * scale * scale * scale)
    return f;
  const double cof[9] = {
      a[4] * a[8] - a[5] * a[7], a[2] * a[7] - a[1] * a[8], a[1] * a[5] - a[2] * a[4],
      a[5] * a[6] - a[3] * a[8], a[0] * a[8] - a[2] * a[6], a[2] * a[3] - a[0] * a[5],
      a[3] * a[7] - a[4] * a[6], a[1] * a[6] - a[0] * a[7], a[0] * a[4] - a[1] * a[3]};
  for (int i = 0; i < 9; ++i) f.inverse[i] = cof[i] / det;
  f.invertible = true;
  return f;
}

std::string placeholder_png() {
  const uint16_t grey[3] = {128, 128, 128};
  return encode_png(1, 1, 8, grey);
}

// One primitive: its vertices in its frame, the input's attributes, its faces.
nlohmann::json write_primitive(GlbBuilder& b, const GltfAppearance& look,
                               const GltfAppearance::Primitive& p, const Frame& frame,
                               const SceneGeometry& g) {
  const PolygonMesh& input = *g.input;
  std::vector<Triangle> triangles;
  for (uint32_t f = p.first_face; f < p.first_face + p.face_count; ++f) {
    if ((!g.skip_face.empty() && g.skip_face[f]) || input.face_size(f) != 3) continue;
    const auto c = input.face(f);
    Triangle t = {c[0] - p.first_vertex, c[1] - p.first_vertex, c[2] - p.first_vertex};
    if (p.mirrored) std::swap(t[1], t[2]);  // the file's own winding; the node mirrors it
    triangles.push_back(t);
  }
  if (triangles.empty()) return nullptr;
  const size_t first = p.first_vertex, count = p.vertex_count;
  std::vector<Vec3> local(count), normals;
  for (size_t i = 0; i < count; ++i) local[i] = frame.point_to_local(g.positions[first + i]);
  nlohmann::json attributes;
  attributes["POSITION"] = b.add_vec3(local, true);
  const GltfAppearance::Attribute* input_normals =
      p.has("NORMAL") ? look.attribute("NORMAL") : nullptr;
  if (!g.normals.empty()) {
    for (size_t i = 0; i < count; ++i)
      normals.push_back(frame.normal_to_local(g.normals[first + i]));
    attributes["NORMAL"] = b.add_vec3(normals, false);
  } else if (input_normals) {
    for (size_t i = 0; i < count; ++i) {
      const float* n = &input_normals->values[(first + i) * 3];
      normals.push_back({n[0], n[1], n[2]});
    }
    attributes["NORMAL"] = b.add_vec3(normals, false);
  }
  for (const std::string& name : p.attributes) {
    const GltfAppearance::Attribute* a = look.attribute(name);
    if (name == "NORMAL" || !a) continue;
    const size_t k = static_cast<size_t>(a->components);
    attributes[name] = b.add_floats({a->values.data() + first * k, count * k}, a->components);
  }
  nlohmann::json primitive = {
      {"attributes", attributes}, {"indices", b.add_indices(triangles)}, {"mode", 4}};
  if (p.material >= 0 && static_cast<size_t>(p.material) < look.materials.size())
    primitive["material"] = p.material;
  if (!g.morph_positions.empty()) {
    std::vector<Vec3> offsets(count);
    for (size_t i = 0; i < count; ++i)
      offsets[i] = frame.vector_to_local(g.morph_positions[first + i] - g.positions[first + i]);
    nlohmann::json target = {{"POSITION", b.add_vec3(offsets, true)}};
    if (!normals.empty() && !g.morph_normals.empty()) {
      for (size_t i = 0; i < count; ++i)
        offsets[i] = frame.normal_to_local(g.morph_normals[first + i]) - normals[i];
      target["NORMAL"] = b.add_vec3(offsets, false);
    }
    primitive["targets"] = nlohmann::json::array({target});
  }
  return primitive;
}

}  // namespace

GlbParts build_scene_glb(const GltfAppearance& look, const SceneGeometry& g,
                         const nlohmann::json& extras) {
  GlbBuilder b;
  nlohmann::json nodes = look.nodes, meshes = nlohmann::json::array();
  std::vector<size_t> roots = look.scene_nodes;
  const bool has_nodes = !look.nodes.empty();
  std::map<int64_t, size_t> mesh_of_node;  // -1: the new root node's mesh
  std::vector<size_t> drawing_nodes;
  for (const GltfAppearance::Primitive& p : look.primitives) {
    Frame frame = has_nodes && p.node >= 0 ? frame_of(p.world) : identity_frame();
    int64_t key = has_nodes && p.node >= 0 && frame.invertible ? p.node : -1;
    if (key < 0) frame = identity_frame();
    // Without a usable frame, positions are world space: the identity, under the root.
    nlohmann::json primitive = write_primitive(b, look, p, frame, g);
    if (primitive.is_null()) continue;
    auto [it, added] = mesh_of_node.emplace(key, meshes.size());
    if (added) {
      nlohmann::json mesh = {{"primitives", nlohmann::json::array()}};
      if (!p.mesh_name.empty()) mesh["name"] = p.mesh_name;
      if (!g.morph_positions.empty()) mesh["weights"] = {0.0};
      meshes.push_back(std::move(mesh));
      size_t node = static_cast<size_t>(key);
      if (key < 0) {
        nodes.push_back({{"name", p.mesh_name.empty() ? "mesh" : p.mesh_name}});
        node = nodes.size() - 1;
        roots.push_back(node);
      }
      nodes[node]["mesh"] = it->second;
      drawing_nodes.push_back(node);
    }
    meshes[it->second]["primitives"].push_back(std::move(primitive));
  }
  if (!meshes.empty()) meshes[0]["extras"] = extras;
  // Each distinct image's bytes once, however many images name them (one view each).
  nlohmann::json images = nlohmann::json::array();
  std::map<size_t, size_t> view_of_data;  // image_data entry (kNoImageData: placeholder)
  for (size_t i = 0; i < look.images.size(); ++i) {
    const std::string* bytes = look.image_bytes(i);
    const size_t data = bytes ? look.image_source[i] : GltfAppearance::kNoImageData;
    auto [view, added] = view_of_data.emplace(data, 0);
    if (added) view->second = b.add_view(bytes ? *bytes : placeholder_png());
    nlohmann::json image = look.images[i];
    image["bufferView"] = view->second;
    if (!bytes) image["mimeType"] = "image/png";
    images.push_back(std::move(image));
  }
  nlohmann::json scene = {{"nodes", roots}};
  if (!look.scene_name.empty()) scene["name"] = look.scene_name;
  nlohmann::json json = {{"asset", {{"version", "2.0"}, {"generator", "spheremap"}}},
                         {"scene", 0},
                         {"scenes", nlohmann::json::array({scene})},
                         {"nodes", nodes},
                         {"meshes", meshes}};
  for (const auto& [key, value] :
       {std::pair<const char*, const nlohmann::json&>{"materials", look.materials},
        {"textures", look.textures},
        {"samplers", look.samplers},
        {"cameras", look.cameras},
        {"images", images}})
    if (!value.empty()) json[key] = value;
  if (!g.morph_positions.empty() && g.morph_seconds > 0)
    json["animations"] =
        nlohmann::json::array({morph_animation(b, g.morph_seconds, drawing_nodes)});
  if (!look.extensions_used.empty()) json["extensionsUsed"] = look.extensions_used;
  if (!look.extensions_required.empty()) json["extensionsRequired"] = look.extensions_required;
  json["accessors"] = b.accessors();
  json["bufferViews"] = b.views();
  json["buffers"] = {{{"byteLength", b.bin().size()}}};
  return {std::move(json), std::move(b.bin())};
}

}  // namespace spheremap
