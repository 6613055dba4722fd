#include "core/io/gltf_checked.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spheremap::gltf {
namespace {

using nlohmann::json;

bool is_number_in(const json& value, double low, double high) {
  return value.is_number() && value.get<double>() >= low && value.get<double>() <= high;
}

// An array of `count` numbers, each within [low, high].
bool is_numbers(const json& value, size_t count, double low, double high) {
  if (!value.is_array() || value.size() != count) return false;
  for (const json& x : value)
    if (!is_number_in(x, low, high)) return false;
  return true;
}

// Copies `key` from `from` to `to` when `valid` accepts its value.
template <typename Valid>
void copy_if(const json& from, json& to, const char* key, Valid valid) {
  if (const auto it = from.find(key); it != from.end() && valid(*it)) to[key] = *it;
}

bool is_string(const json& v) {
  return v.is_string();
}
bool is_index(const json& v) {
  return v.is_number_unsigned();
}

using Declared = std::vector<std::string>;

// Only the extensions the output declares, as objects.
json checked_extensions(const json& extensions, const Declared& declared) {
  json out = json::object();
  if (!extensions.is_object()) return out;
  for (const auto& [name, value] : extensions.items())
    if (value.is_object() && std::find(declared.begin(), declared.end(), name) != declared.end())
      out[name] = value;
  return out;
}

// A textureInfo (and the members normalTexture and occlusionTexture add). Its index was
// checked to resolve before (texture_references_resolve).
json checked_texture_info(const json& info, const Declared& declared, const char* extra,
                          double extra_low, double extra_high) {
  json out = json::object();
  copy_if(info, out, "index", is_index);
  copy_if(info, out, "texCoord", is_index);
  if (extra)
    copy_if(info, out, extra,
            [&](const json& v) { return is_number_in(v, extra_low, extra_high); });
  if (info.contains("extensions"))
    if (json e = checked_extensions(info["extensions"], declared); !e.empty())
      out["extensions"] = e;
  return out;
}

void copy_texture_info(const json& from, json& to, const char* key, const Declared& declared,
                       const char* extra = nullptr, double extra_low = 0, double extra_high = 0) {
  if (const auto it = from.find(key); it != from.end() && it->is_object() && it->contains("index"))
    to[key] = checked_texture_info(*it, declared, extra, extra_low, extra_high);
}

}  // namespace

std::optional<std::array<double, 4>> usable_rotation(std::span<const double> q) {
  if (q.size() != 4) return std::nullopt;
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(length) || length < 1e-12) return std::nullopt;
  // Kept bit for bit when unit to float32 precision, so that outputs of valid files do
  // not change; glTF-Validator allows about the same.
  const double scale = std::abs(length - 1) <= 1e-6 ? 1 : 1 / length;
  return std::array<double, 4>{q[0] * scale, q[1] * scale, q[2] * scale, q[3] * scale};
}

json checked_node(const json& node, size_t cameras) {
  json out = json::object();
  if (!node.is_object()) return out;
  copy_if(node, out, "name", is_string);
  copy_if(node, out, "children", [](const json& v) { return v.is_array() && !v.empty(); });
  copy_if(node, out, "camera",
          [&](const json& v) { return is_index(v) && v.get<size_t>() < cameras; });
  const double huge = std::numeric_limits<double>::max();
  if (node.contains("matrix")) {  // the reader applies the matrix and ignores TRS
    copy_if(node, out, "matrix", [&](const json& v) { return is_numbers(v, 16, -huge, huge); });
    return out;
  }
  copy_if(node, out, "translation", [&](const json& v) { return is_numbers(v, 3, -huge, huge); });
  copy_if(node, out, "scale", [&](const json& v) { return is_numbers(v, 3, -huge, huge); });
  if (const auto it = node.find("rotation"); it != node.end() && is_numbers(*it, 4, -huge, huge)) {
    const auto given = it->get<std::vector<double>>();
    if (const auto q = usable_rotation(given))
      out["rotation"] = std::equal(q->begin(), q->end(), given.begin()) ? *it : json(*q);
  }
  return out;
}

json checked_material(const json& material, const Declared& declared) {
  json out = json::object();
  if (!material.is_object()) return out;
  copy_if(material, out, "name", is_string);
  if (const auto pbr = material.find("pbrMetallicRoughness");
      pbr != material.end() && pbr->is_object()) {
    json p = json::object();
    copy_if(*pbr, p, "baseColorFactor", [](const json& v) { return is_numbers(v, 4, 0, 1); });
    copy_if(*pbr, p, "metallicFactor", [](const json& v) { return is_number_in(v, 0, 1); });
    copy_if(*pbr, p, "roughnessFactor", [](const json& v) { return is_number_in(v, 0, 1); });
    copy_texture_info(*pbr, p, "baseColorTexture", declared);
    copy_texture_info(*pbr, p, "metallicRoughnessTexture", declared);
    out["pbrMetallicRoughness"] = std::move(p);
  }
  const double huge = std::numeric_limits<double>::max();
  copy_texture_info(material, out, "normalTexture", declared, "scale", -huge, huge);
  copy_texture_info(material, out, "occlusionTexture", declared, "strength", 0, 1);
  copy_texture_info(material, out, "emissiveTexture", declared);
  copy_if(material, out, "emissiveFactor", [](const json& v) { return is_numbers(v, 3, 0, 1); });
  copy_if(material, out, "alphaMode",
          [](const json& v) { return v == "OPAQUE" || v == "MASK" || v == "BLEND"; });
  copy_if(material, out, "alphaCutoff", [&](const json& v) { return is_number_in(v, 0, huge); });
  copy_if(material, out, "doubleSided", [](const json& v) { return v.is_boolean(); });
  if (material.contains("extensions"))
    if (json e = checked_extensions(material["extensions"], declared); !e.empty())
      out["extensions"] = e;
  if (material.contains("extras")) out["extras"] = material["extras"];
  return out;
}

json checked_texture(const json& texture, const Declared& declared) {
  json out = json::object();
  if (!texture.is_object()) return out;
  copy_if(texture, out, "sampler", is_index);
  copy_if(texture, out, "source", is_index);
  copy_if(texture, out, "name", is_string);
  if (texture.contains("extensions"))
    if (json e = checked_extensions(texture["extensions"], declared); !e.empty())
      out["extensions"] = e;
  return out;
}

}  // namespace spheremap::gltf
