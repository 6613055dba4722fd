#include "core/io/gltf_reader.h"

#include <draco/compression/decode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <span>

#include "core/io/draco_header.h"
#include "core/io/gltf1_upgrade.h"
#include "core/io/gltf_checked.h"
#include "core/io/gltf_document.h"
#include "core/io/gltf_look.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

using gltf::fail;
using gltf::range_field;
using Matrix = Matrix4;

constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
constexpr int kMaxNodeDepth = 64;

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) m[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return m;
}

std::vector<double> numbers(const nlohmann::json& node, const char* key, size_t n) {
  const auto it = node.find(key);
  if (it == node.end()) return {};
  if (!it->is_array() || it->size() != n)
    fail(std::string("node ") + key + " must have " + std::to_string(n) + " numbers");
  std::vector<double> v;
  for (const auto& x : *it) {
    if (!x.is_number()) fail(std::string("node ") + key + " holds a non-number");
    v.push_back(x.get<double>());
  }
  return v;
}

// T * R * S of a translation (3 numbers), a rotation (a quaternion x y z w, made usable
// as gltf_checked.h says) and a scale (3 numbers); an empty one is the identity.
Matrix compose_trs(std::span<const double> translation, std::span<const double> rotation,
                   std::span<const double> scale) {
  Matrix t = kIdentity;
  if (!translation.empty()) t[12] = translation[0], t[13] = translation[1], t[14] = translation[2];
  Matrix r = kIdentity;
  // A non-unit quaternion is normalized (the writers write it so: gltf_checked.h).
  if (const auto q = gltf::usable_rotation(rotation)) {
    const auto [x, y, z, w] = *q;
    r = {1 - 2 * (y * y + z * z),
         2 * (x * y + z * w),
         2 * (x * z - y * w),
         0,
         2 * (x * y - z * w),
         1 - 2 * (x * x + z * z),
         2 * (y * z + x * w),
         0,
         2 * (x * z + y * w),
         2 * (y * z - x * w),
         1 - 2 * (x * x + y * y),
         0,
         0,
         0,
         0,
         1};
  }
  Matrix s = kIdentity;
  if (!scale.empty()) s[0] = scale[0], s[5] = scale[1], s[10] = scale[2];
  return multiply(t, multiply(r, s));
}

Matrix local_transform(const nlohmann::json& node) {
  if (auto m = numbers(node, "matrix", 16); !m.empty()) {
    Matrix out;
    std::copy(m.begin(), m.end(), out.begin());
    return out;
  }
  return compose_trs(numbers(node, "translation", 3), numbers(node, "rotation", 4),
                     numbers(node, "scale", 3));
}

class Reader {
  // A primitive's attribute (other than POSITION) before it joins the appearance.
  struct LookAttribute {
    std::string name;
    int components;
    std::vector<double> values;
  };

 public:
  Reader(std::span<const uint8_t> bytes, const GltfReadOptions& options, GltfReadStats& stats,
         const GltfResources* resources, GltfAppearance* look)
      : doc_(bytes, resources,
             {decode_budget(options), options.max_resource_bytes, &options.should_stop}),
        options_(options),
        stats_(stats),
        look_(look) {}

  bool read_as_gltf1() const { return doc_.read_as_gltf1(); }

  PolygonMesh read() {
    const nlohmann::json& json = doc_.json();
    const size_t mesh_count =
        json.contains("meshes") && json["meshes"].is_array() ? json["meshes"].size() : 0;
    if (mesh_count == 0) fail("the file has no meshes");
    draws_.assign(mesh_count, 0);
    const bool has_scene =
        json.contains("scenes") && json["scenes"].is_array() && !json["scenes"].empty();
    if (options_.mesh_index >= 0 || !options_.mesh_name.empty()) {
      // The chosen mesh as its first node draws it (quantized positions need that node's
      // transform), or as stored when no node does.
      chosen_ = chosen_mesh(mesh_count);
      if (has_scene) walk_scene();
      if (!chosen_drawn_) add_mesh(chosen_, kIdentity, -1);
    } else if (has_scene) {
      walk_scene();
    } else {
      for (size_t m = 0; m < mesh_count; ++m) add_mesh(m, kIdentity, -1);
    }
    if (look_) copy_look(*look_);
    stats_.warnings = doc_.warnings();
    if (positionless_ > 0) {
      const std::string which =
          first_positionless_ + " has no POSITION attribute" +
          (positionless_ > 1 ? " (nor " + std::to_string(positionless_ - 1) + " more primitives)"
                             : std::string());
      // Nothing else to read: the file's fault as before (magnum's mesh.glb has two drawn
      // meshes beside two empty ones, and was refused whole).
      if (mesh_.face_count() == 0) fail(which);
      stats_.warnings.push_back(which + ": skipped, as viewers skip it (it draws nothing)");
    }
    for (size_t m = 0; m < mesh_count; ++m)
      if (draws_[m] > 1 && (stats_.repeated_mesh < 0 || draws_[m] > stats_.repeated_mesh_draws))
        stats_.repeated_mesh = static_cast<int>(m), stats_.repeated_mesh_draws = draws_[m];
    // Nothing to map (points or lines only): the check the other readers and the mesh
    // checks give a mesh without faces, not a malformed file.
    if (mesh_.face_count() == 0 && point_primitives_ > 0 &&
        point_primitives_ == stats_.skipped_primitives && stats_.primitives == 0)
      throw InputError("empty", "the file is a point cloud (" + counted(points_, "point") +
                                    ", no faces): spheremap maps triangle surfaces");
    if (mesh_.face_count() == 0)
      throw InputError(
          "empty", "no triangles to map: " + std::to_string(stats_.skipped_primitives) +
                       " primitive(s) of points or lines, " + std::to_string(stats_.primitives) +
                       " of triangles");
    return std::move(mesh_);
  }

 private:
  static size_t decode_budget(const GltfReadOptions& options) {
    // Room for interleaved vertex data and 32-bit indices at the caps, no more.
    return options.max_vertices * 64 + options.max_triangles * 12;
  }

  void walk_scene() {
    const nlohmann::json& json = doc_.json();
    const size_t chosen = doc_.reference(json, "scene", "scenes", "the top-level scene field");
    const size_t scene = chosen == SIZE_MAX ? 0 : chosen;
    const nlohmann::json& s = doc_.element("scenes", scene);
    if (const auto nodes = s.find("nodes"); nodes != s.end() && nodes->is_array())
      for (const auto& n : *nodes) {
        const size_t root =
            doc_.reference(n, "nodes", "scene " + std::to_string(scene) + " refers to");
        visit(root, kIdentity, 0);
        scene_roots_.push_back(root);
      }
    if (const auto name = s.find("name"); name != s.end() && name->is_string())
      scene_name_ = name->get<std::string>();
  }

  size_t chosen_mesh(size_t mesh_count) {
    if (!options_.mesh_name.empty()) {
      for (size_t m = 0; m < mesh_count; ++m) {
        const auto& mesh = doc_.element("meshes", m);
        if (mesh.contains("name") && mesh["name"] == options_.mesh_name) return m;
      }
      fail("no mesh is named '" + options_.mesh_name + "'");
    }
    if (static_cast<size_t>(options_.mesh_index) >= mesh_count)
      fail("mesh " + std::to_string(options_.mesh_index) + " does not exist (" +
           std::to_string(mesh_count) + " meshes)");
    return static_cast<size_t>(options_.mesh_index);
  }

  // glTF 2.0 nodes form a forest: a node has at most one parent and no cycles. A node
  // reached twice is refused, which also bounds the walk by the node count (measured: a
  // 916-byte file whose 40 nodes each list the next one twice was 2^41 visits).
  void visit(size_t node_index, const Matrix& parent, int depth) {
    if (depth > kMaxNodeDepth)
      fail("node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " (a cycle?)");
    const nlohmann::json& node = doc_.element("nodes", node_index);
    if (visited_.size() <= node_index) visited_.resize(doc_.json()["nodes"].size(), 0);
    if (visited_[node_index])
      fail("node " + std::to_string(node_index) +
           " is reached twice; glTF nodes must form a tree (one parent each)");
    visited_[node_index] = 1;
    const Matrix world = multiply(parent, local_transform(node));
    const std::string name = "node " + std::to_string(node_index);
    if (const size_t mesh = doc_.reference(node, "mesh", "meshes", name); mesh != SIZE_MAX)
      draw(node_index, node, mesh, world);
    if (const auto children = node.find("children"); children != node.end() && children->is_array())
      for (const auto& c : *children)
        visit(doc_.reference(c, "nodes", name + "'s children refer to"), world, depth + 1);
  }

  void draw(size_t node_index, const nlohmann::json& node, size_t mesh, const Matrix& world) {
    ++draws_[mesh];
    const auto node_id = static_cast<int64_t>(node_index);
    if (chosen_ == SIZE_MAX) {
      const InstanceTransforms instances = gpu_instances(node, node_index, mesh);
      if (instances.count == 0) return add_mesh(mesh, world, node_id);
      // Each instance is a copy of the mesh in world space, as a viewer draws it, and an
      // asset of copies maps part by part. Its primitives belong to no node (-1: the
      // outputs write them in world space): the node's one transform is not theirs.
      draws_[mesh] += instances.count - 1;
      for (size_t i = 0; i < instances.count; ++i)
        add_mesh(mesh, multiply(world, instances.matrix(i)), -1);
      return;
    }
    if (mesh == chosen_ && !chosen_drawn_) {
      chosen_drawn_ = true;
      add_mesh(mesh, world, node_id);
    }
  }

  // EXT_mesh_gpu_instancing's per-instance TRANSLATION, ROTATION and SCALE, decoded.
  struct InstanceTransforms {
    size_t count = 0;  // 0: the node draws the mesh once, with its own transform
    std::vector<double> translation, rotation, scale;  // 3, 4 and 3 per instance, or empty
    Matrix matrix(size_t i) const {
      auto slice = [i](const std::vector<double>& v, size_t n) {
        return v.empty() ? std::span<const double>{} : std::span<const double>(v).subspan(i * n, n);
      };
      return compose_trs(slice(translation, 3), slice(rotation, 4), slice(scale, 3));
    }
  };

  // The node's instances. Their count is capped (kMaxInstanceCopies in all), and times the
  // mesh's vertices checked against the vertex cap, before any is read.
  InstanceTransforms gpu_instances(const nlohmann::json& node, size_t node_index, size_t mesh) {
    const auto ext = node.find("extensions");
    if (ext == node.end() || !ext->is_object() || !ext->contains("EXT_mesh_gpu_instancing"))
      return {};
    const std::string name = "node " + std::to_string(node_index) + "'s EXT_mesh_gpu_instancing";
    const nlohmann::json& instancing = (*ext)["EXT_mesh_gpu_instancing"];
    if (!instancing.is_object() || !instancing.contains("attributes") ||
        !instancing["attributes"].is_object() || instancing["attributes"].empty())
      fail(name + " has no attributes");
    const nlohmann::json& attributes = instancing["attributes"];
    InstanceTransforms out;
    bool counted = false;
    for (const auto& [key, components] :
         {std::pair<const char*, int>{"TRANSLATION", 3}, {"ROTATION", 4}, {"SCALE", 3}}) {
      const size_t accessor = doc_.reference(attributes, key, "accessors", name);
      if (accessor == SIZE_MAX) continue;
      const auto shape = doc_.accessor_shape(accessor);
      if (shape.components != components)
        fail(name + "'s " + key + " has " + std::to_string(shape.components) + " components, not " +
             std::to_string(components));
      if (counted && shape.count != out.count)
        fail(name + "'s attributes differ in count (" + std::to_string(out.count) + " and " +
             std::to_string(shape.count) + ")");
      out.count = shape.count, counted = true;
    }
    if (out.count == 0) return out;  // no transform attribute: custom ones only, drawn once
    // Each copy is a part to prepare (a copy's map is its original's turned: map_parts.h):
    // 1,500 instances of a 5,120-face open sphere (7.7M triangles) map in 41 s and 2.7 GB
    // (session 51). Past the cap the mesh is to be mapped once, as before instances were
    // read; the service's vertex cap (below) refuses far fewer.
    instance_copies_ += out.count;
    if (instance_copies_ > kMaxInstanceCopies) {
      const std::string m = std::to_string(mesh);
      throw InputError("instancing",
                       name + " draws mesh " + m + " as " + std::to_string(out.count) +
                           " instances; spheremap reads at most " +
                           std::to_string(kMaxInstanceCopies) +
                           " instances in all, each a part to map",
                       {"mesh", m, "maps mesh " + m + " once"});
    }
    const size_t per_instance = std::max<size_t>(mesh_vertices(mesh), 1);
    if (out.count > (options_.max_vertices - mesh_.vertex_count()) / per_instance)
      throw InputError("too_large", name + " draws mesh " + std::to_string(mesh) + " " +
                                        std::to_string(out.count) + " times, " +
                                        std::to_string(per_instance) +
                                        " vertices each: over the limit of " +
                                        std::to_string(options_.max_vertices) + " vertices");
    int components = 0;
    for (const auto& [key, values] :
         {std::pair<const char*, std::vector<double>*>{"TRANSLATION", &out.translation},
          {"ROTATION", &out.rotation},
          {"SCALE", &out.scale}})
      if (const size_t a = doc_.reference(attributes, key, "accessors", name); a != SIZE_MAX)
        *values = doc_.read_attribute(a, &components);
    return out;
  }

  // The vertices mesh `mesh`'s primitives declare (their POSITION accessors' counts).
  size_t mesh_vertices(size_t mesh) const {
    const nlohmann::json& m = doc_.element("meshes", mesh);
    size_t total = 0;
    if (const auto primitives = m.find("primitives");
        primitives != m.end() && primitives->is_array())
      for (const auto& p : *primitives)
        if (p.is_object() && p.contains("attributes") && p["attributes"].is_object() &&
            p["attributes"].contains("POSITION"))
          if (const size_t a = doc_.reference(p["attributes"], "POSITION", "accessors",
                                              "mesh " + std::to_string(mesh));
              a != SIZE_MAX)
            total += doc_.accessor_shape(a).count;
    return total;
  }

  static constexpr size_t kMaxInstanceCopies = 2048;
  size_t instance_copies_ = 0;                // EXT_mesh_gpu_instancing copies read so far
  std::vector<char> visited_;                 // nodes reached by the scene walk
  std::vector<size_t> draws_;                 // per mesh, how many nodes draw it
  size_t chosen_ = SIZE_MAX;                  // --mesh: the one mesh to read
  size_t point_primitives_ = 0, points_ = 0;  // POINTS primitives skipped, their points
  // Triangle primitives without POSITION (the spec allows it; they draw nothing), skipped,
  // and the first one's name for the report.
  size_t positionless_ = 0;
  std::string first_positionless_;
  bool chosen_drawn_ = false;

  void add_mesh(size_t mesh_index, const Matrix& world, int64_t node) {
    const nlohmann::json& mesh = doc_.element("meshes", mesh_index);
    const auto primitives = mesh.find("primitives");
    if (primitives == mesh.end() || !primitives->is_array())
      fail("mesh " + std::to_string(mesh_index) + " has no primitives");
    const size_t faces_before = mesh_.face_count();
    for (size_t k = 0; k < primitives->size(); ++k) {
      const nlohmann::json& p = (*primitives)[k];
      const std::string name =
          "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(k);
      if (!p.is_object()) fail(name + " is not an object");
      add_primitive(p, world, node, mesh, name);
    }
    auto& drawn = stats_.drawn_meshes;
    const auto known = std::find_if(drawn.begin(), drawn.end(),
                                    [&](const auto& d) { return d.index == mesh_index; });
    if (known == drawn.end()) {
      const auto name = mesh.find("name");
      drawn.push_back({mesh_index, mesh_.face_count() - faces_before,
                       name != mesh.end() && name->is_string() ? name->get<std::string>() : ""});
    }
  }

  // `name` ("mesh 0 primitive 1") locates the primitive in refusals.
  void add_primitive(const nlohmann::json& p, const Matrix& world, int64_t node,
                     const nlohmann::json& mesh, const std::string& name) {
    const size_t mode = range_field(p, "mode", 0, 6, name + "'s mode", 4);
    if (mode < 4) {
      ++stats_.skipped_primitives;
      if (mode == 0) count_points(p);
      return;
    }
    ++stats_.primitives;
    std::vector<double> positions;
    std::vector<uint32_t> indices;
    std::vector<LookAttribute> carried;
    const auto ext = p.find("extensions");
    if (ext != p.end() && ext->is_object() && ext->contains("KHR_draco_mesh_compression")) {
      decode_draco((*ext)["KHR_draco_mesh_compression"], positions, indices,
                   look_ ? &carried : nullptr, name);
      ++stats_.draco_primitives;
    } else {
      // Counts against the caps before anything is decoded. The indices' reference (and
      // their accessor's view and buffer) first: a dangling one is the file's fault, told
      // as such, where a missing POSITION is only what it lacks.
      const size_t ia = doc_.reference(p, "indices", "accessors", name);
      if (ia != SIZE_MAX) check_room(0, triangles_from(doc_.accessor_shape(ia).count, mode));
      const auto attributes = p.find("attributes");
      if (attributes == p.end() || !attributes->is_object() || !attributes->contains("POSITION")) {
        --stats_.primitives;
        if (positionless_++ == 0) first_positionless_ = name;
        return;
      }
      const size_t position_accessor = doc_.reference(*attributes, "POSITION", "accessors", name);
      check_room(doc_.accessor_shape(position_accessor).count, 0);
      positions = doc_.read_positions(position_accessor);
      const size_t vertex_count = positions.size() / 3;
      if (ia != SIZE_MAX) {
        indices = doc_.read_indices(ia, vertex_count);
      } else {
        indices.resize(vertex_count);
        for (uint32_t i = 0; i < vertex_count; ++i) indices[i] = i;
      }
      if (look_) carried = look_attributes(*attributes, vertex_count);
    }
    // Strips and fans make up to 3 indices of each one: counted before they are made.
    check_room(0, triangles_from(indices.size(), mode));
    doc_.tick(64);  // a primitive costs something however small: many of them are asked about
    const size_t first_vertex = mesh_.vertex_count(), first_face = mesh_.face_count();
    const bool mirrored = append(positions, triangles_of(indices, mode), world);
    if (!look_) return;
    GltfAppearance::Primitive record;
    record.node = node;
    const size_t material = doc_.reference(p, "material", "materials", name);
    record.material = material == SIZE_MAX ? -1 : static_cast<int64_t>(material);
    if (const auto name = mesh.find("name"); name != mesh.end() && name->is_string())
      record.mesh_name = name->get<std::string>();
    record.first_vertex = static_cast<uint32_t>(first_vertex);
    record.vertex_count = static_cast<uint32_t>(mesh_.vertex_count() - first_vertex);
    record.first_face = static_cast<uint32_t>(first_face);
    record.face_count = static_cast<uint32_t>(mesh_.face_count() - first_face);
    record.world = world;
    // Mirrored faces were flipped on read; an output that writes them under their node
    // flips them back (the node mirrors them), one in world space (no node) does not.
    record.mirrored = mirrored && node >= 0;
    for (const LookAttribute& a : carried) {
      record.attributes.push_back(a.name);
      store_attribute(a, first_vertex, record.vertex_count);
    }
    look_->primitives.push_back(std::move(record));
  }

  // The triangles `indices` indices make in `mode` (TRIANGLES, strip or fan).
  static size_t triangles_from(size_t indices, size_t mode) {
    return mode == 4 ? indices / 3 : std::max<size_t>(indices, 2) - 2;
  }

  static std::vector<uint32_t> triangles_of(const std::vector<uint32_t>& idx, size_t mode) {
    if (mode == 4) {
      if (idx.size() % 3)
        fail("a TRIANGLES primitive has " + std::to_string(idx.size()) +
             " indices, not a multiple of 3");
      return idx;
    }
    std::vector<uint32_t> tris;
    for (size_t k = 2; k < idx.size(); ++k) {
      if (mode == 5)  // strip: alternate the winding
        k % 2 ? tris.insert(tris.end(), {idx[k - 1], idx[k - 2], idx[k]})
              : tris.insert(tris.end(), {idx[k - 2], idx[k - 1], idx[k]});
      else  // fan
        tris.insert(tris.end(), {idx[0], idx[k - 1], idx[k]});
    }
    return tris;
  }

  void decode_draco(const nlohmann::json& draco_ext, std::vector<double>& positions,
                    std::vector<uint32_t>& indices, std::vector<LookAttribute>* look,
                    const std::string& primitive) {
    if (!draco_ext.is_object()) fail("KHR_draco_mesh_compression is not an object");
    const size_t view = doc_.reference(draco_ext, "bufferView", "bufferViews",
                                       primitive + "'s KHR_draco_mesh_compression");
    if (view == SIZE_MAX) fail("KHR_draco_mesh_compression has no bufferView");
    const std::span<const uint8_t> bytes = doc_.buffer_view(view);
    const auto attributes = draco_ext.find("attributes");
    if (attributes == draco_ext.end() || !attributes->is_object() ||
        !attributes->contains("POSITION"))
      fail("KHR_draco_mesh_compression has no POSITION attribute");
    const size_t position_id =
        range_field(*attributes, "POSITION", 0, UINT32_MAX - 1, "Draco POSITION id");
    // The counts the stream declares, against what is left of the caps, before Draco
    // allocates by them.
    const DracoCounts declared = read_draco_counts(bytes);
    if (declared.faces > options_.max_triangles - mesh_.face_count() ||
        declared.vertices > options_.max_vertices - mesh_.vertex_count())
      throw InputError("too_large", "a Draco primitive declares " +
                                        std::to_string(declared.vertices) + " vertices and " +
                                        std::to_string(declared.faces) +
                                        " triangles, over what is left of the limits (" +
                                        std::to_string(options_.max_vertices) + " vertices, " +
                                        std::to_string(options_.max_triangles) + " triangles)");
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok() || !decoded.value()) fail("the Draco data does not decode as a mesh");
    const draco::Mesh& mesh = *decoded.value();
    const draco::PointAttribute* attribute =
        mesh.GetAttributeByUniqueId(static_cast<uint32_t>(position_id));
    if (!attribute || attribute->num_components() != 3)
      fail("the Draco data has no 3-component attribute with id " + std::to_string(position_id));
    // Draco converts a bool attribute by loading its bytes as bool (undefined behaviour for
    // any byte but 0 and 1): positions are numbers.
    if (attribute->data_type() == draco::DT_BOOL || attribute->data_type() == draco::DT_INVALID)
      fail("the Draco POSITION attribute is not numeric");
    const size_t points = mesh.num_points();
    if (points > options_.max_vertices)
      throw InputError("too_large", "the Draco mesh has " + std::to_string(points) +
                                        " vertices, over the limit of " +
                                        std::to_string(options_.max_vertices));
    positions.resize(points * 3);
    for (uint32_t i = 0; i < points; ++i) {
      std::array<float, 3> v{};
      if (!attribute->ConvertValue<float>(attribute->mapped_index(draco::PointIndex(i)), 3,
                                          v.data()))
        fail("a Draco position does not convert to float");
      for (int c = 0; c < 3; ++c) positions[3 * i + c] = v[static_cast<size_t>(c)];
    }
    if (look) *look = draco_look_attributes(mesh, *attributes);
    indices.resize(static_cast<size_t>(mesh.num_faces()) * 3);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) {
        const uint32_t id = mesh.face(draco::FaceIndex(f))[c].value();
        if (id >= points) fail("a Draco face refers past the decoded vertices");
        indices[3 * f + static_cast<size_t>(c)] = id;
      }
  }

  // A POINTS primitive's points, for the refusal of a point cloud: its POSITION accessor's
  // declared count (checked against its view, not decoded). A primitive without a usable
  // one counts none: it is skipped either way.
  void count_points(const nlohmann::json& p) {
    ++point_primitives_;
    const auto attributes = p.find("attributes");
    if (attributes == p.end() || !attributes->is_object()) return;
    const auto position = attributes->find("POSITION");
    const size_t accessors =
        doc_.json().contains("accessors") ? doc_.json()["accessors"].size() : 0;
    if (position == attributes->end() || !position->is_number_unsigned() ||
        position->get<size_t>() >= accessors)
      return;
    try {
      points_ += doc_.accessor_shape(position->get<size_t>()).count;
    } catch (const InputError&) {
      // A malformed accessor of a skipped primitive was never read: not a reason to refuse.
    }
  }

  // Refuses (too_large) what would take the mesh past the caps.
  void check_room(size_t vertices, size_t triangles) const {
    if (vertices > options_.max_vertices - mesh_.vertex_count())
      throw InputError(
          "too_large",
          "the meshes have over " + std::to_string(options_.max_vertices) + " vertices, the limit");
    if (triangles > options_.max_triangles - mesh_.face_count())
      throw InputError("too_large", "the meshes have over " +
                                        std::to_string(options_.max_triangles) +
                                        " triangles, the limit");
  }

  // Returns whether the transform mirrors (its faces were flipped to keep them outward).
  bool append(const std::vector<double>& positions, const std::vector<uint32_t>& tris,
              const Matrix& m) {
    const uint32_t base = static_cast<uint32_t>(mesh_.vertex_count());
    const size_t count = positions.size() / 3;
    check_room(count, tris.size() / 3);
    for (size_t i = 0; i < count; ++i) {
      doc_.tick();
      const double x = positions[3 * i], y = positions[3 * i + 1], z = positions[3 * i + 2];
      mesh_.positions.push_back({m[0] * x + m[4] * y + m[8] * z + m[12],
                                 m[1] * x + m[5] * y + m[9] * z + m[13],
                                 m[2] * x + m[6] * y + m[10] * z + m[14]});
    }
    // A mirroring transform (negative determinant) flips the winding back.
    const double det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
                       m[8] * (m[1] * m[6] - m[5] * m[2]);
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
      doc_.tick();
      const uint32_t f[3] = {base + tris[t], base + (det < 0 ? tris[t + 2] : tris[t + 1]),
                             base + (det < 0 ? tris[t + 1] : tris[t + 2])};
      mesh_.add_face(f);
    }
    return det < 0;
  }

  gltf::Document doc_;
  const GltfReadOptions& options_;
  GltfReadStats& stats_;
  PolygonMesh mesh_;

  // The look, read only when asked for (read_gltf's `appearance`).
  GltfAppearance* look_;
  std::vector<size_t> scene_roots_;
  std::string scene_name_;

  static bool carried_attribute(const std::string& name) {
    return name == "NORMAL" || name == "COLOR_0" ||
           (name.rfind("TEXCOORD_", 0) == 0 && name.size() == 10 && name[9] >= '0' &&
            name[9] <= '3');
  }
  static int carried_components(const std::string& name) {
    return name == "NORMAL" ? 3 : name == "COLOR_0" ? 4 : 2;
  }

  // Whether an accessor of this shape may hold the attribute `name` (glTF 2.0, with
  // KHR_mesh_quantization's integer NORMAL and TEXCOORD): NORMAL VEC3 float or normalized
  // (short) byte; TEXCOORD_n VEC2 float or (short) byte; COLOR_0 VEC3 or VEC4, float or
  // normalized unsigned (short) byte.
  static bool shape_fits(const std::string& name, const gltf::Document::AccessorShape& a) {
    const int type = a.component_type;
    const bool is_float = type == 5126;
    if (name == "NORMAL")
      return a.components == 3 && (is_float || (a.normalized && (type == 5120 || type == 5122)));
    if (name == "COLOR_0")
      return (a.components == 3 || a.components == 4) &&
             (is_float || (a.normalized && (type == 5121 || type == 5123)));
    return a.components == 2 && (is_float || (type >= 5120 && type <= 5123));
  }

  // The carried attributes of a plain primitive. One that does not fit (a count other
  // than POSITION's, a type glTF does not allow for it) is left out before it is decoded:
  // the look is a courtesy, never a reason to refuse a mappable mesh, nor to spend time
  // on (measured: 2,000 three-vertex primitives naming one 16 MB MAT4 accessor as their
  // TEXCOORD_0 were decoded 2,000 times, 4 s each). Each accessor is decoded once.
  std::vector<LookAttribute> look_attributes(const nlohmann::json& attributes,
                                             size_t vertex_count) {
    std::vector<LookAttribute> out;
    const size_t accessors =
        doc_.json().contains("accessors") ? doc_.json()["accessors"].size() : 0;
    for (const auto& [name, value] : attributes.items()) {
      if (!carried_attribute(name) || !value.is_number_unsigned() ||
          value.get<uint64_t>() >= accessors)
        continue;
      const size_t accessor = value.get<size_t>();
      std::vector<double> values;
      int components = 0;
      try {
        const gltf::Document::AccessorShape shape = doc_.accessor_shape(accessor);
        if (shape.count != vertex_count || !shape_fits(name, shape)) continue;
        values = decoded_attribute(accessor, &components);
      } catch (const InputError& e) {
        if (e.check() != "gltf") throw;  // a limit or a stop is not the accessor's fault
        continue;                        // a broken UV accessor costs the UVs, not the map
      }
      if (auto fitted = fitted_attribute(name, components, std::move(values)))
        out.push_back(std::move(*fitted));
    }
    return out;
  }

  // Accessor `index` decoded, once for all the primitive attributes that name it: kept
  // until the last of them (by the JSON's count) has taken it, not kept when only one
  // does (the usual file: no copy of its attributes beyond the look's own).
  std::vector<double> decoded_attribute(size_t index, int* components) {
    size_t& uses_left = attribute_references()[index];
    if (uses_left > 0) --uses_left;
    if (const auto kept = decoded_attributes_.find(index); kept != decoded_attributes_.end()) {
      *components = kept->second.first;
      if (uses_left > 0) return kept->second.second;
      std::vector<double> last = std::move(kept->second.second);
      decoded_attributes_.erase(kept);
      return last;
    }
    std::vector<double> values = doc_.read_attribute(index, components);
    if (uses_left > 0) decoded_attributes_.emplace(index, std::make_pair(*components, values));
    return values;
  }

  // Per accessor, how many carried attributes of the file's primitives name it.
  std::map<size_t, size_t>& attribute_references() {
    if (references_counted_) return attribute_references_;
    references_counted_ = true;
    const nlohmann::json& json = doc_.json();
    if (!json.contains("meshes") || !json["meshes"].is_array()) return attribute_references_;
    for (const auto& mesh : json["meshes"]) {
      const auto primitives = mesh.is_object() ? mesh.find("primitives") : mesh.end();
      if (primitives == mesh.end() || !primitives->is_array()) continue;
      for (const auto& p : *primitives) {
        const auto attributes = p.is_object() ? p.find("attributes") : p.end();
        if (attributes == p.end() || !attributes->is_object()) continue;
        for (const auto& [name, value] : attributes->items())
          if (carried_attribute(name) && value.is_number_unsigned())
            ++attribute_references_[value.get<size_t>()];
      }
    }
    return attribute_references_;
  }
  std::map<size_t, std::pair<int, std::vector<double>>> decoded_attributes_;
  std::map<size_t, size_t> attribute_references_;
  bool references_counted_ = false;

  std::vector<LookAttribute> draco_look_attributes(const draco::Mesh& mesh,
                                                   const nlohmann::json& ids) const {
    std::vector<LookAttribute> out;
    for (const auto& [name, id] : ids.items()) {
      if (!carried_attribute(name) || !id.is_number_unsigned() || id.get<uint64_t>() > UINT32_MAX)
        continue;
      const draco::PointAttribute* attribute =
          mesh.GetAttributeByUniqueId(static_cast<uint32_t>(id.get<uint64_t>()));
      if (!attribute || attribute->num_components() < 1 || attribute->num_components() > 4 ||
          attribute->data_type() == draco::DT_BOOL || attribute->data_type() == draco::DT_INVALID)
        continue;  // bool: see decode_draco
      const int components = attribute->num_components();
      std::vector<double> values(static_cast<size_t>(mesh.num_points()) * components);
      std::array<float, 4> v{};
      for (uint32_t i = 0; i < mesh.num_points(); ++i) {
        if (!attribute->ConvertValue<float>(attribute->mapped_index(draco::PointIndex(i)),
                                            static_cast<int8_t>(components), v.data()))
          break;
        for (int c = 0; c < components; ++c)
          values[static_cast<size_t>(i) * components + c] = v[static_cast<size_t>(c)];
      }
      if (auto fitted = fitted_attribute(name, components, std::move(values)))
        out.push_back(std::move(*fitted));
    }
    return out;
  }

  // The attribute with the components the writer uses (COLOR_0 RGB gets alpha 1), or
  // nothing when its component count is not one glTF allows for it.
  static std::optional<LookAttribute> fitted_attribute(const std::string& name, int components,
                                                       std::vector<double> values) {
    const int wanted = carried_components(name);
    if (components == wanted) return LookAttribute{name, components, std::move(values)};
    if (name != "COLOR_0" || components != 3) return std::nullopt;
    const size_t count = values.size() / 3;
    std::vector<double> rgba(count * 4, 1.0);
    for (size_t i = 0; i < count; ++i)
      for (size_t c = 0; c < 3; ++c) rgba[i * 4 + c] = values[i * 3 + c];
    return LookAttribute{name, 4, std::move(rgba)};
  }

  void store_attribute(const LookAttribute& a, size_t first_vertex, size_t count) {
    auto& list = look_->attributes;
    auto it = std::find_if(list.begin(), list.end(),
                           [&](const GltfAppearance::Attribute& x) { return x.name == a.name; });
    if (it == list.end()) {
      list.push_back({a.name, a.components, {}});
      it = list.end() - 1;
    }
    const size_t stride = static_cast<size_t>(a.components);
    it->values.resize(mesh_.vertex_count() * stride, 0.0f);
    for (size_t i = 0; i < count * stride; ++i)
      it->values[first_vertex * stride + i] = static_cast<float>(a.values[i]);
  }

  void copy_look(GltfAppearance& look) const {
    for (GltfAppearance::Attribute& a : look.attributes)
      a.values.resize(mesh_.vertex_count() * static_cast<size_t>(a.components), 0.0f);
    gltf::copy_scene_look(doc_, scene_roots_, scene_name_, visited_, look);
  }
};

}  // namespace

PolygonMesh read_gltf(std::span<const uint8_t> bytes, const GltfReadOptions& options,
                      GltfReadStats* stats, const GltfResources* resources,
                      GltfAppearance* appearance) {
  GltfReadStats local;
  if (appearance) *appearance = {};
  Reader reader(bytes, options, stats ? *stats : local, resources, appearance);
  try {
    return reader.read();
  } catch (const InputError& e) {
    if (!reader.read_as_gltf1()) throw;
    throw gltf::in_upgrade(e);
  }
}

void suggest_gltf_fixes(std::vector<ValidationFailure>& failures, const GltfReadStats& stats) {
  const bool caused_by_parts =
      std::any_of(failures.begin(), failures.end(), [](const ValidationFailure& f) {
        return f.check == "non_manifold_edge" || f.check == "non_manifold_vertex" ||
               f.check == "components";
      });
  if (!caused_by_parts) return;
  if (stats.repeated_mesh >= 0) {
    const std::string m = std::to_string(stats.repeated_mesh);
    failures.front().fix = {"mesh", m,
                            "maps mesh " + m + " alone (the scene draws it " +
                                std::to_string(stats.repeated_mesh_draws) + " times)"};
  }
  if (stats.drawn_meshes.size() < 2) return;
  // The meshes, so that one can be picked by index or name (at most 8, names cut at 40).
  // Not a fix: whether one maps alone is not known here (it was 18 times out of 35 that
  // none did, on real kits), so the list says what the option reads, not that it maps.
  std::string list = "; the scene draws " + std::to_string(stats.drawn_meshes.size()) +
                     " meshes (the mesh option reads one of them alone; whether it maps "
                     "is not checked):";
  for (size_t i = 0; i < stats.drawn_meshes.size() && i < 8; ++i) {
    const auto& d = stats.drawn_meshes[i];
    list += (i ? ", " : " ") + std::to_string(d.index);
    if (!d.name.empty()) list += " '" + d.name.substr(0, 40) + "'";
    list += " (" + std::to_string(d.triangles) + " triangles)";
  }
  if (stats.drawn_meshes.size() > 8) list += ", ...";
  failures.front().message += list;
}

}  // namespace spheremap
