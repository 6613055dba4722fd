#include "core/io/gltf1_upgrade.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/io/bounded_json.h"
#include "core/io/byte_order.h"
#include "core/io/gltf_document.h"

namespace spheremap::gltf {
namespace {

using nlohmann::json;

[[noreturn]] void fail1(const std::string& message) {
  fail("glTF 1.0: " + message);
}

uint32_t read_u32(std::span<const uint8_t> bytes, size_t at) {
  return load_little_endian<uint32_t>(bytes.data() + at);
}

// One of 1.0's top-level dictionaries (accessors, nodes, ...): its objects in the order
// they become 2.0's array, and each id's index there.
struct Dictionary {
  std::string noun;  // "accessor", for messages
  std::vector<std::pair<std::string, const json*>> entries;
  std::map<std::string, size_t> index;

  void add(const std::string& id, const json& object) {
    if (!object.is_object()) fail1(noun + " " + describe_json(id) + " is not an object");
    index.emplace(id, entries.size());
    entries.emplace_back(id, &object);
  }
  // The 2.0 index of the id `value`, or fail naming the referrer and the id.
  size_t operator()(const json& value, const std::string& referrer) const {
    if (value.is_string())
      if (const auto it = index.find(value.get_ref<const std::string&>()); it != index.end())
        return it->second;
    fail1(referrer + " refers to " + noun + " " + describe_json(value) +
          ", which the file does not have");
  }
  std::string name(size_t i) const { return noun + " " + describe_json(entries[i].first); }
};

// `key`'s dictionary; `first`, when the file has that id, is given index 0.
Dictionary dictionary(const json& v1, const char* key, const char* noun,
                      const char* first = nullptr) {
  Dictionary d{noun, {}, {}};
  const auto it = v1.find(key);
  if (it == v1.end()) return d;
  if (!it->is_object())
    fail1(std::string(key) + " is not an object (glTF 1.0 keys its " + key + " by id)");
  if (first)
    if (const auto f = it->find(first); f != it->end()) d.add(first, *f);
  for (const auto& [id, object] : it->items())
    if (!first || id != first) d.add(id, object);
  return d;
}

uint64_t whole(const json& object, const char* key, const std::string& owner, uint64_t fallback) {
  return whole_field(object, key, "glTF 1.0: " + owner, "a non-negative integer")
      .value_or(fallback);
}

void copy_fields(const json& from, json& to, std::initializer_list<const char*> keys) {
  for (const char* key : keys)
    if (const auto it = from.find(key); it != from.end()) to[key] = *it;
}

// A 1.0 array of ids (a node's children, a scene's nodes) as 2.0 indices.
json indices(const json& owner, const char* key, const Dictionary& d, const std::string& name) {
  json out = json::array();
  const auto it = owner.find(key);
  if (it == owner.end()) return out;
  if (!it->is_array()) fail1(name + "'s " + key + " is not an array");
  for (const json& id : *it) out.push_back(d(id, name + "'s " + key));
  return out;
}

// The vertex attributes 2.0 defines that spheremap reads; 1.0's others (joints, weights,
// technique-specific names) are dropped.
bool kept_semantic(const std::string& name) {
  if (name == "POSITION" || name == "NORMAL") return true;
  for (const std::string prefix : {"TEXCOORD_", "COLOR_"})
    if (name.size() > prefix.size() && name.size() <= prefix.size() + 2 &&
        name.rfind(prefix, 0) == 0 &&
        std::all_of(name.begin() + prefix.size(), name.end(),
                    [](char c) { return c >= '0' && c <= '9'; }))
      return true;
  return false;
}

struct Dictionaries {
  Dictionary buffers, views, accessors, meshes, nodes, scenes, materials, textures, images,
      samplers;
};

json upgraded_accessors(const Dictionaries& d, json& views) {
  // Each accessor gets a bufferView of its own: 1.0 keeps byteStride on the accessor and
  // lets accessors of different strides share a view, which 2.0 cannot say.
  json out = json::array();
  for (size_t i = 0; i < d.accessors.entries.size(); ++i) {
    const json& a = *d.accessors.entries[i].second;
    const std::string name = d.accessors.name(i);
    if (const auto ext = a.find("extensions");
        ext != a.end() && ext->is_object() && ext->contains("WEB3D_quantized_attributes"))
      fail1(name +
            " is quantized (WEB3D_quantized_attributes), which spheremap does not decode; "
            "convert the file to glTF 2.0 first, e.g. with gltf-pipeline");
    json a2 = json::object();
    copy_fields(a, a2, {"componentType", "count", "type", "min", "max", "name"});
    if (const auto view_id = a.find("bufferView"); view_id != a.end()) {
      const size_t v = d.views(*view_id, name);
      const json& view = *d.views.entries[v].second;
      const std::string view_name = d.views.name(v);
      const auto buffer = view.find("buffer");
      if (buffer == view.end()) fail1(view_name + " has no buffer");
      const uint64_t view_offset = whole(view, "byteOffset", view_name, 0);
      const uint64_t view_length = whole(view, "byteLength", view_name, UINT64_MAX);
      if (view_length == UINT64_MAX) fail1(view_name + " has no byteLength");
      const uint64_t offset = whole(a, "byteOffset", name, 0);
      if (offset > view_length)
        fail1(name + "'s byteOffset " + std::to_string(offset) + " is past the end of " +
              view_name + " (" + std::to_string(view_length) + " bytes)");
      if (view_offset > UINT64_MAX - offset)
        fail1(name + "'s byteOffset does not fit in 64 bits with its view's");
      json own = {{"buffer", d.buffers(*buffer, view_name)},
                  {"byteOffset", view_offset + offset},
                  {"byteLength", view_length - offset}};
      // 0 is 1.0's "tightly packed", which 2.0 says by leaving byteStride out.
      if (const uint64_t stride = whole(a, "byteStride", name, 0); stride > 0)
        own["byteStride"] = stride;
      a2["bufferView"] = views.size();
      views.push_back(std::move(own));
    }
    out.push_back(std::move(a2));
  }
  return out;
}

json upgraded_meshes(const Dictionaries& d) {
  json out = json::array();
  for (size_t i = 0; i < d.meshes.entries.size(); ++i) {
    const json& m = *d.meshes.entries[i].second;
    const std::string name = d.meshes.name(i);
    json m2 = {{"primitives", json::array()}};
    copy_fields(m, m2, {"name"});
    const auto primitives = m.find("primitives");
    if (primitives == m.end() || !primitives->is_array())
      fail1(name + " has no array of primitives");
    for (size_t k = 0; k < primitives->size(); ++k) {
      const json& p = (*primitives)[k];
      const std::string owner = name + " primitive " + std::to_string(k);
      if (!p.is_object()) fail1(owner + " is not an object");
      json p2 = {{"attributes", json::object()}};
      if (const auto attributes = p.find("attributes"); attributes != p.end()) {
        if (!attributes->is_object()) fail1(owner + "'s attributes is not an object");
        for (const auto& [semantic, id] : attributes->items())
          if (kept_semantic(semantic))
            p2["attributes"][semantic] = d.accessors(id, owner + "'s " + semantic);
      }
      if (const auto it = p.find("indices"); it != p.end())
        p2["indices"] = d.accessors(*it, owner + " (its indices)");
      if (const auto it = p.find("material"); it != p.end())
        p2["material"] = d.materials(*it, owner);
      copy_fields(p, p2, {"mode"});
      m2["primitives"].push_back(std::move(p2));
    }
    out.push_back(std::move(m2));
  }
  return out;
}

json upgraded_nodes(const Dictionaries& d) {
  json out = json::array();
  json added = json::array();  // one node per mesh of a node of several meshes
  for (size_t i = 0; i < d.nodes.entries.size(); ++i) {
    const json& n = *d.nodes.entries[i].second;
    const std::string name = d.nodes.name(i);
    json n2 = json::object();
    copy_fields(n, n2, {"name", "matrix", "translation", "rotation", "scale"});
    json children = indices(n, "children", d.nodes, name);
    const json meshes = indices(n, "meshes", d.meshes, name);
    if (meshes.size() == 1) {
      n2["mesh"] = meshes[0];
    } else {
      for (const json& mesh : meshes) {
        children.push_back(d.nodes.entries.size() + added.size());
        added.push_back({{"mesh", mesh}});
      }
    }
    if (!children.empty()) n2["children"] = std::move(children);
    out.push_back(std::move(n2));
  }
  for (json& n : added) out.push_back(std::move(n));
  return out;
}

// The default value of the technique's parameter `parameter` (techniques.T.parameters.P.value),
// what a material that names the technique and gives no value of its own gets; null when
// anything on the way is missing or malformed (techniques are otherwise dropped, unchecked).
const json* technique_default(const json& v1, const json& material, const char* parameter) {
  const auto technique = material.find("technique");
  const auto techniques = v1.find("techniques");
  if (technique == material.end() || !technique->is_string() || techniques == v1.end() ||
      !techniques->is_object())
    return nullptr;
  const auto t = techniques->find(technique->get_ref<const std::string&>());
  if (t == techniques->end() || !t->is_object()) return nullptr;
  const auto parameters = t->find("parameters");
  if (parameters == t->end() || !parameters->is_object()) return nullptr;
  const auto p = parameters->find(parameter);
  if (p == parameters->end() || !p->is_object()) return nullptr;
  const auto value = p->find("value");
  return value == p->end() ? nullptr : &*value;
}

// A 1.0 material's diffuse colour or texture as 2.0's base colour; 1.0 materials are
// shader parameters, and "diffuse" is what its common techniques and exporters name it.
// Without a value of its own, its technique's default (COLLADA2GLTF writes a material's
// constant colour there).
json upgraded_material(const json& v1, const Dictionaries& d, size_t i) {
  const json& m = *d.materials.entries[i].second;
  const std::string name = d.materials.name(i);
  json m2 = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}};
  copy_fields(m, m2, {"name"});
  const json* values = nullptr;
  if (const auto ext = m.find("extensions"); ext != m.end() && ext->is_object())
    if (const auto common = ext->find("KHR_materials_common");
        common != ext->end() && common->is_object()) {
      if (const auto it = common->find("values"); it != common->end()) values = &*it;
      if (const auto it = common->find("doubleSided"); it != common->end() && it->is_boolean())
        m2["doubleSided"] = *it;
    }
  if (!values)
    if (const auto it = m.find("values"); it != m.end()) values = &*it;
  const json* diffuse = nullptr;
  if (values && values->is_object())
    if (const auto it = values->find("diffuse"); it != values->end()) diffuse = &*it;
  if (!diffuse) diffuse = technique_default(v1, m, "diffuse");
  if (!diffuse) return m2;
  if (diffuse->is_string()) {
    m2["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", d.textures(*diffuse, name + "'s diffuse")}};
  } else if (diffuse->is_array() && (diffuse->size() == 3 || diffuse->size() == 4) &&
             std::all_of(diffuse->begin(), diffuse->end(),
                         [](const json& c) { return c.is_number(); })) {
    json factor = json::array();
    for (const json& c : *diffuse) factor.push_back(std::clamp(c.get<double>(), 0.0, 1.0));
    if (factor.size() == 3) factor.push_back(1.0);
    m2["pbrMetallicRoughness"]["baseColorFactor"] = std::move(factor);
  }
  return m2;
}

json upgraded_images(const Dictionaries& d) {
  json out = json::array();
  for (size_t i = 0; i < d.images.entries.size(); ++i) {
    const json& image = *d.images.entries[i].second;
    json i2 = json::object();
    copy_fields(image, i2, {"uri", "name"});
    if (const auto ext = image.find("extensions"); ext != image.end() && ext->is_object())
      if (const auto binary = ext->find("KHR_binary_glTF");
          binary != ext->end() && binary->is_object() && binary->contains("bufferView")) {
        i2["bufferView"] = d.views((*binary)["bufferView"], d.images.name(i));
        copy_fields(*binary, i2, {"mimeType"});
      }
    out.push_back(std::move(i2));
  }
  return out;
}

json upgraded_textures(const Dictionaries& d) {
  json out = json::array();
  for (size_t i = 0; i < d.textures.entries.size(); ++i) {
    const json& t = *d.textures.entries[i].second;
    json t2 = json::object();
    if (const auto it = t.find("source"); it != t.end())
      t2["source"] = d.images(*it, d.textures.name(i));
    if (const auto it = t.find("sampler"); it != t.end())
      t2["sampler"] = d.samplers(*it, d.textures.name(i));
    out.push_back(std::move(t2));
  }
  return out;
}

// CESIUM_RTC: positions are relative to a centre, which becomes a root node's translation.
void add_rtc_centre(const json& v1, json& v2) {
  const auto ext = v1.find("extensions");
  if (ext == v1.end() || !ext->is_object() || !ext->contains("CESIUM_RTC")) return;
  const json& rtc = (*ext)["CESIUM_RTC"];
  const auto centre = rtc.is_object() ? rtc.find("center") : rtc.end();
  if (centre == rtc.end() || !centre->is_array() || centre->size() != 3 ||
      !std::all_of(centre->begin(), centre->end(), [](const json& c) { return c.is_number(); }))
    fail1("CESIUM_RTC has no center of three numbers");
  for (json& scene : v2["scenes"]) {
    json root = {{"translation", *centre}, {"children", scene["nodes"]}};
    scene["nodes"] = json::array({v2["nodes"].size()});
    v2["nodes"].push_back(std::move(root));
  }
}

}  // namespace

InputError in_upgrade(const InputError& e) {
  if (e.check() != "gltf") return e;
  return InputError("gltf",
                    std::string(e.what()) +
                        " (read through this glTF 1.0 file's 2.0 upgrade, whose objects are "
                        "numbered in the order of their ids)",
                    e.fix());
}

bool declares_gltf1(const json& json) {
  const auto asset = json.find("asset");
  if (asset == json.end() || !asset->is_object()) return false;
  const auto version = asset->find("version");
  if (version == asset->end()) return false;
  if (version->is_string()) {
    const std::string& v = version->get_ref<const std::string&>();
    return v == "1" || v.rfind("1.", 0) == 0;
  }
  return version->is_number() && version->get<double>() >= 1 && version->get<double>() < 2;
}

void split_glb1(std::span<const uint8_t> bytes, std::span<const uint8_t>* json_text,
                std::span<const uint8_t>* body) {
  if (bytes.size() < 20)
    fail("GLB 1.0 is truncated: " + std::to_string(bytes.size()) + " bytes, its header is 20");
  const uint64_t length = read_u32(bytes, 8), content = read_u32(bytes, 12);
  if (length > bytes.size())
    fail("GLB header declares " + std::to_string(length) + " bytes but the file has " +
         std::to_string(bytes.size()));
  if (read_u32(bytes, 16) != 0)
    fail("GLB 1.0 content format " + std::to_string(read_u32(bytes, 16)) + " is not JSON (0)");
  if (length < 20 || content > length - 20)
    fail("GLB 1.0 declares " + std::to_string(content) + " bytes of JSON, past its length of " +
         std::to_string(length) + " bytes");
  *json_text = bytes.subspan(20, content);
  *body = bytes.subspan(20 + content, length - 20 - content);
}

json upgrade_gltf1(const json& v1, bool has_body) {
  const Dictionaries d{dictionary(v1, "buffers", "buffer", has_body ? "binary_glTF" : nullptr),
                       dictionary(v1, "bufferViews", "bufferView"),
                       dictionary(v1, "accessors", "accessor"),
                       dictionary(v1, "meshes", "mesh"),
                       dictionary(v1, "nodes", "node"),
                       dictionary(v1, "scenes", "scene"),
                       dictionary(v1, "materials", "material"),
                       dictionary(v1, "textures", "texture"),
                       dictionary(v1, "images", "image"),
                       dictionary(v1, "samplers", "sampler")};
  json v2 = {{"asset", {{"version", "2.0"}, {"generator", "spheremap's glTF 1.0 reader"}}}};

  json buffers = json::array();
  for (size_t i = 0; i < d.buffers.entries.size(); ++i) {
    const auto& [id, b] = d.buffers.entries[i];
    json b2 = json::object();
    copy_fields(*b, b2, {"byteLength", "name"});
    // KHR_binary_glTF's buffer is the GLB body, which 2.0 reads as buffer 0 without a uri.
    if (!(has_body && i == 0 && id == "binary_glTF")) copy_fields(*b, b2, {"uri"});
    buffers.push_back(std::move(b2));
  }
  v2["buffers"] = std::move(buffers);

  json views = json::array();
  for (size_t i = 0; i < d.views.entries.size(); ++i) {
    const json& view = *d.views.entries[i].second;
    json v = json::object();
    copy_fields(view, v, {"byteOffset", "byteLength", "name"});
    if (const auto buffer = view.find("buffer"); buffer != view.end())
      v["buffer"] = d.buffers(*buffer, d.views.name(i));
    views.push_back(std::move(v));
  }
  v2["accessors"] = upgraded_accessors(d, views);
  v2["bufferViews"] = std::move(views);
  v2["meshes"] = upgraded_meshes(d);
  v2["nodes"] = upgraded_nodes(d);

  json scenes = json::array();
  for (size_t i = 0; i < d.scenes.entries.size(); ++i)
    scenes.push_back(
        {{"nodes", indices(*d.scenes.entries[i].second, "nodes", d.nodes, d.scenes.name(i))}});
  v2["scenes"] = std::move(scenes);
  if (const auto it = v1.find("scene"); it != v1.end()) v2["scene"] = d.scenes(*it, "the file");
  add_rtc_centre(v1, v2);

  json materials = json::array();
  for (size_t i = 0; i < d.materials.entries.size(); ++i)
    materials.push_back(upgraded_material(v1, d, i));
  v2["materials"] = std::move(materials);
  v2["textures"] = upgraded_textures(d);
  v2["images"] = upgraded_images(d);
  json samplers = json::array();
  for (const auto& entry : d.samplers.entries) {
    json s = json::object();
    copy_fields(*entry.second, s, {"magFilter", "minFilter", "wrapS", "wrapT"});
    samplers.push_back(std::move(s));
  }
  v2["samplers"] = std::move(samplers);
  // Empty arrays are not valid 2.0 (and some readers treat "present" as "has one").
  for (const char* key : {"buffers", "bufferViews", "accessors", "meshes", "nodes", "scenes",
                          "materials", "textures", "images", "samplers"})
    if (v2[key].empty()) v2.erase(key);
  return v2;
}

}  // namespace spheremap::gltf
