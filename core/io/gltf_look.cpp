#include "core/io/gltf_look.h"

#include <algorithm>
#include <map>

#include "core/io/gltf_checked.h"
#include "core/io/image_reader.h"
#include "core/mesh/input_error.h"

namespace spheremap::gltf {
namespace {

size_t array_size(const nlohmann::json& json, const char* key) {
  const auto it = json.find(key);
  return it != json.end() && it->is_array() ? it->size() : 0;
}

nlohmann::json array_of(const nlohmann::json& json, const char* key) {
  const auto it = json.find(key);
  return it != json.end() && it->is_array() ? *it : nlohmann::json::array();
}

bool index_below(const nlohmann::json& value, size_t limit) {
  return value.is_number_unsigned() && value.get<uint64_t>() < limit;
}

// Every texture reference in a material ({"index": i} under a key ending in "Texture",
// at any depth: the core material and its extensions) points at an existing texture.
bool texture_references_resolve(const nlohmann::json& value, size_t textures, int depth = 0) {
  if (depth > 16) return false;
  if (value.is_array()) {
    for (const auto& v : value)
      if (!texture_references_resolve(v, textures, depth + 1)) return false;
    return true;
  }
  if (!value.is_object()) return true;
  for (const auto& [key, member] : value.items()) {
    const bool texture_info = key.size() > 7 && key.compare(key.size() - 7, 7, "Texture") == 0;
    if (texture_info && (!member.is_object() || !member.contains("index") ||
                         !index_below(member["index"], textures)))
      return false;
    if (!texture_references_resolve(member, textures, depth + 1)) return false;
  }
  return true;
}

// A texture's image and sampler (also an image extension's "source") exist.
bool texture_resolves(const nlohmann::json& texture, size_t images, size_t samplers) {
  if (!texture.is_object()) return false;
  if (texture.contains("source") && !index_below(texture["source"], images)) return false;
  if (texture.contains("sampler") && !index_below(texture["sampler"], samplers)) return false;
  if (const auto ext = texture.find("extensions"); ext != texture.end()) {
    if (!ext->is_object()) return false;
    for (const auto& [name, e] : ext->items())
      if (e.is_object() && e.contains("source") && !index_below(e["source"], images)) return false;
  }
  return true;
}

// Which bytes an image names, so that images naming the same ones share one copy: its
// bufferView or its URI (data: or a file); empty when it names neither.
std::string image_source_key(const nlohmann::json& image) {
  if (!image.is_object()) return "";
  if (const auto view = image.find("bufferView"); view != image.end())
    return "view:" + view->dump();
  if (const auto uri = image.find("uri"); uri != image.end() && uri->is_string())
    return "uri:" + uri->get<std::string>();
  return "";
}

std::vector<std::string> appearance_extensions(const nlohmann::json& json, const char* key) {
  std::vector<std::string> out;
  for (const auto& e : array_of(json, key))
    if (e.is_string() && material_extension(e.get<std::string>()))
      out.push_back(e.get<std::string>());
  return out;
}

// A sampler with only the members glTF defines, each only with a value glTF allows (so an
// input's odd sampler does not make every output invalid).
nlohmann::json checked_sampler(const nlohmann::json& sampler) {
  static const std::map<std::string, std::vector<int>> kAllowed = {
      {"magFilter", {9728, 9729}},
      {"minFilter", {9728, 9729, 9984, 9985, 9986, 9987}},
      {"wrapS", {33071, 33648, 10497}},
      {"wrapT", {33071, 33648, 10497}}};
  nlohmann::json out = nlohmann::json::object();
  if (!sampler.is_object()) return out;
  for (const auto& [key, values] : kAllowed)
    if (const auto it = sampler.find(key); it != sampler.end() && it->is_number_integer() &&
                                           std::count(values.begin(), values.end(), it->get<int>()))
      out[key] = *it;
  if (sampler.contains("name") && sampler["name"].is_string()) out["name"] = sampler["name"];
  return out;
}

}  // namespace

void copy_scene_look(const Document& doc, const std::vector<size_t>& roots,
                     const std::string& scene_name, const std::vector<char>& visited,
                     GltfAppearance& look) {
  const nlohmann::json& json = doc.json();
  const size_t images = array_size(json, "images"), samplers = array_size(json, "samplers");
  look.cameras = array_of(json, "cameras");
  for (const auto& sampler : array_of(json, "samplers"))
    look.samplers.push_back(checked_sampler(sampler));
  look.textures = array_of(json, "textures");
  look.materials = array_of(json, "materials");
  bool resolves = true;
  for (const auto& t : look.textures) resolves = resolves && texture_resolves(t, images, samplers);
  for (const auto& m : look.materials)
    resolves = resolves && m.is_object() && texture_references_resolve(m, look.textures.size());
  if (!resolves) {
    // Broken references would make every output invalid; the geometry still maps.
    look.materials = look.textures = look.samplers = nlohmann::json::array();
    for (auto& p : look.primitives) p.material = -1;
  } else {
    look.extensions_used = appearance_extensions(json, "extensionsUsed");
    look.extensions_required = appearance_extensions(json, "extensionsRequired");
    for (auto& m : look.materials) m = checked_material(m, look.extensions_used);
    for (auto& t : look.textures) t = checked_texture(t, look.extensions_used);
    std::map<std::string, size_t> data_of_source;  // image_source_key -> image_data entry
    std::vector<std::string> types;                // per image_data entry
    for (size_t i = 0; i < images; ++i) {
      const nlohmann::json& image = json["images"][i];
      const std::string key = image_source_key(image);
      size_t data = GltfAppearance::kNoImageData;
      if (const auto known = data_of_source.find(key);
          !key.empty() && known != data_of_source.end()) {
        data = known->second;
      } else {
        std::string bytes;
        try {
          if (image.is_object()) bytes = doc.image_bytes(i).value_or("");
        } catch (const InputError& e) {
          // An image we cannot read is replaced, not a reason to refuse; a limit is.
          if (e.check() != "gltf") throw;
          bytes.clear();
        }
        if (std::string type = image_type(bytes); !type.empty()) {
          data = look.image_data.size();
          look.image_data.push_back(std::move(bytes));
          types.push_back(std::move(type));
        }
        if (!key.empty()) data_of_source.emplace(key, data);
      }
      nlohmann::json copy = nlohmann::json::object();
      if (image.is_object() && image.contains("name") && image["name"].is_string())
        copy["name"] = image["name"];
      copy["mimeType"] = data == GltfAppearance::kNoImageData ? "image/png" : types[data];
      look.images.push_back(std::move(copy));
      look.image_source.push_back(data);
    }
  }
  if (!roots.empty()) {
    const size_t cameras = look.cameras.size();
    for (size_t n = 0; n < array_size(json, "nodes"); ++n)
      look.nodes.push_back(n < visited.size() && visited[n]
                               ? checked_node(json["nodes"][n], cameras)
                               : nlohmann::json::object());
    look.scene_nodes = roots;
    look.scene_name = scene_name;
  }
}

}  // namespace spheremap::gltf
