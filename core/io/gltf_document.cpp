#include "core/io/gltf_document.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>

#include "core/io/bounded_json.h"
#include "core/io/byte_order.h"
#include "core/io/gltf1_upgrade.h"
#include "core/io/meshopt_view.h"
#include "core/io/shown_bytes.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap::gltf {
namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kJsonChunk = 0x4E4F534A;
constexpr uint32_t kBinChunk = 0x004E4942;
// A GLB chunk's length is a uint32: no external buffer may be larger either.
constexpr size_t kMaxResourceBytes = UINT32_MAX;

// Extensions a file may require that change what is drawn, not where: materials,
// textures, lights. The geometry ones read here are listed separately.
bool appearance_only(const std::string& name) {
  return material_extension(name) || name == "KHR_lights_punctual" || name == "KHR_xmp_json_ld";
}
// Custom GLSL shading (glTF 1.0's techniques carried into 2.0 by converters). Its vertex
// shaders could in principle move vertices; they are not run, the geometry is read as stored
// and a warning says so, as three.js's loader does with extensions it lacks (set 5: 4 of
// gltf-pipeline's test files were refused for it).
constexpr const char* kShaderExtension = "KHR_techniques_webgl";
const char* const kGeometryExtensions[] = {"KHR_draco_mesh_compression", "KHR_mesh_quantization",
                                           "EXT_meshopt_compression", "KHR_meshopt_compression",
                                           "EXT_mesh_gpu_instancing"};
// The meshopt compression extensions: the vendor one and its Khronos successor, which has the
// same JSON and adds a vertex codec version and a filter (meshopt_view.h).
const char* const kMeshoptExtensions[] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};

// The meshopt extension object of a buffer or bufferView's `extensions`, and its name; null
// when it has none.
std::pair<const nlohmann::json*, const char*> meshopt_extension(const nlohmann::json& object) {
  const auto extensions = object.find("extensions");
  if (extensions == object.end() || !extensions->is_object()) return {nullptr, nullptr};
  for (const char* name : kMeshoptExtensions)
    if (const auto it = extensions->find(name); it != extensions->end()) return {&*it, name};
  return {nullptr, nullptr};
}

uint32_t read_u32(std::span<const uint8_t> bytes, size_t at) {
  return load_little_endian<uint32_t>(bytes.data() + at);
}

std::string decode_base64(std::string_view text, StopCheck& stop) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::string out;
  out.reserve(text.size() / 4 * 3);
  uint32_t accumulator = 0;
  int bits = 0;
  for (char c : text) {
    stop.tick();
    if (c == '=') break;
    const int v = value(c);
    if (v < 0) fail("a data: URI holds a character that is not base64");
    accumulator = (accumulator << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>(accumulator >> bits));
    }
  }
  return out;
}

size_t component_size(int type) {
  switch (type) {
    case 5120:  // BYTE
    case 5121:  // UNSIGNED_BYTE
      return 1;
    case 5122:  // SHORT
    case 5123:  // UNSIGNED_SHORT
      return 2;
    case 5125:  // UNSIGNED_INT
    case 5126:  // FLOAT
      return 4;
    default:
      return 0;
  }
}

int component_count(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

}  // namespace

bool material_extension(const std::string& name) {
  return name.rfind("KHR_materials_", 0) == 0 || name == "KHR_texture_transform" ||
         name == "KHR_texture_basisu" || name == "EXT_texture_webp" || name == "EXT_texture_avif";
}

void fail(const std::string& message) {
  throw InputError("gltf", message);
}

// A GLB starts with its magic, glTF JSON with '{' after optional whitespace (and a
// UTF-8 byte order mark, which the JSON parser skips too).
bool looks_like_gltf(std::span<const uint8_t> bytes) {
  if (bytes.size() >= 4 && read_u32(bytes, 0) == kGlbMagic) return true;
  size_t at = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF ? 3 : 0;
  while (at < bytes.size() && std::isspace(bytes[at])) ++at;
  return at == bytes.size() || bytes[at] == '{';
}

size_t range_field(const nlohmann::json& object, const char* key, uint64_t min, uint64_t max,
                   const std::string& what, size_t fallback) {
  auto it = object.find(key);
  if (it == object.end()) return fallback;
  if (!it->is_number_unsigned() || it->get<uint64_t>() < min || it->get<uint64_t>() > max)
    fail(what + " " + describe_json(*it) + " is not an integer from " + std::to_string(min) +
         " to " + std::to_string(max));
  return static_cast<size_t>(it->get<uint64_t>());
}

std::optional<uint64_t> whole_field(const nlohmann::json& object, const char* key,
                                    const std::string& owner, const std::string& expected) {
  const auto it = object.find(key);
  if (it == object.end()) return std::nullopt;
  if (!it->is_number_unsigned())
    fail(owner + "'s " + key + " " + describe_json(*it) + " is not " + expected);
  return it->get<uint64_t>();
}

Document::Document(std::span<const uint8_t> bytes, const GltfResources* resources,
                   const DocumentLimits& limits)
    : resources_(resources),
      resource_limit_(limits.max_resource_bytes),
      resource_budget_(limits.max_resource_bytes),
      stop_(limits.should_stop),
      decode_budget_(limits.max_decoded_bytes) {
  std::span<const uint8_t> json_text = bytes, bin;
  bool has_bin = false;
  if (bytes.empty()) fail("empty file (0 bytes)");
  if (!looks_like_gltf(bytes))
    fail(
        "not glTF: neither a GLB (which starts with \"glTF\") nor glTF JSON (which starts "
        "with '{'); the file starts with " +
        shown_prefix({reinterpret_cast<const char*>(bytes.data()), bytes.size()}));
  const bool glb = bytes.size() >= 4 && read_u32(bytes, 0) == kGlbMagic;
  if (glb && bytes.size() < 20)
    fail("GLB is truncated: " + std::to_string(bytes.size()) + " bytes");
  const uint32_t glb_version = glb ? read_u32(bytes, 4) : 0;
  if (glb && glb_version != 1 && glb_version != 2)
    fail("GLB version " + std::to_string(glb_version) + " is not 1 or 2");
  if (glb_version == 1) {  // glTF 1.0's KHR_binary_glTF container
    split_glb1(bytes, &json_text, &bin);
    has_bin = true;
  }
  if (glb_version == 2) {
    const uint32_t length = read_u32(bytes, 8);
    if (length > bytes.size())
      fail("GLB header declares " + std::to_string(length) + " bytes but the file has " +
           std::to_string(bytes.size()));
    size_t at = 12;
    bool first = true;
    while (at + 8 <= length) {
      const uint64_t chunk_length = read_u32(bytes, at), type = read_u32(bytes, at + 4);
      if (at + 8 + chunk_length > length)
        fail("GLB chunk at byte " + std::to_string(at) + " declares " +
             std::to_string(chunk_length) + " bytes, past the end of the file");
      const std::span<const uint8_t> data = bytes.subspan(at + 8, chunk_length);
      if (first && type != kJsonChunk) fail("GLB does not start with a JSON chunk");
      if (first) json_text = data;
      if (!first && type == kBinChunk && !has_bin) bin = data, has_bin = true;
      first = false;
      at += 8 + chunk_length;
    }
    if (first) fail("GLB has no JSON chunk");
  }
  try {
    json_ = parse_bounded_json(
        std::string_view(reinterpret_cast<const char*>(json_text.data()), json_text.size()));
  } catch (const InputError& e) {
    fail(std::string("the glTF JSON is ") + e.what());
  }
  if (json_.is_discarded() || !json_.is_object()) fail("the glTF JSON does not parse as an object");
  // glTF 1.0 is read as the 2.0 document it upgrades to (gltf1_upgrade.h), which is then
  // checked like any other.
  if (declares_gltf1(json_)) {
    json_ = upgrade_gltf1(json_, has_bin);
    read_as_gltf1_ = true;
  }
  const auto asset = json_.find("asset");
  const nlohmann::json* version =
      asset != json_.end() && asset->is_object() && asset->contains("version")
          ? &(*asset)["version"]
          : nullptr;
  if (!version || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0)
    fail("not a glTF 2.0 asset (asset.version must be \"2.x\", or 1.x for glTF 1.0)");
  try {
    check_required_extensions();
    load_buffers(bin, has_bin);
  } catch (const InputError& e) {
    if (!read_as_gltf1_) throw;
    throw in_upgrade(e);
  }
}

bool Document::uses_extension(const char* name) const {
  for (const char* key : {"extensionsUsed", "extensionsRequired"})
    if (const auto it = json_.find(key); it != json_.end() && it->is_array())
      for (const auto& e : *it)
        if (e == name) return true;
  return false;
}

void Document::check_required_extensions() const {
  const auto it = json_.find("extensionsRequired");
  if (it == json_.end()) return;
  if (!it->is_array()) fail("extensionsRequired is not an array");
  for (const auto& e : *it) {
    if (!e.is_string()) fail("extensionsRequired holds a non-string");
    const std::string& name = e.get_ref<const std::string&>();
    if (appearance_only(name) || name == kShaderExtension) continue;
    if (std::find(std::begin(kGeometryExtensions), std::end(kGeometryExtensions), name) !=
        std::end(kGeometryExtensions))
      continue;
    fail("the file requires the extension " + describe_json(e) +
         ", which spheremap does not read (geometry extensions read: KHR_draco_mesh_compression, "
         "KHR_mesh_quantization, EXT_meshopt_compression, KHR_meshopt_compression, "
         "EXT_mesh_gpu_instancing)");
  }
}

void Document::load_buffers(std::span<const uint8_t> bin, bool has_bin) {
  const auto it = json_.find("buffers");
  if (it == json_.end()) return;
  if (!it->is_array()) fail("buffers is not an array");
  std::vector<std::string> missing;
  placeholder_.assign(it->size(), Empty::kNo);
  for (size_t i = 0; i < it->size(); ++i) {
    const nlohmann::json& b = (*it)[i];
    if (!b.is_object()) fail("buffer " + std::to_string(i) + " is not an object");
    const std::string name = "buffer " + std::to_string(i);
    const std::optional<uint64_t> length =
        whole_field(b, "byteLength", name, "a byte count (a non-negative integer)");
    if (!length) fail(name + " has no byteLength");
    const uint64_t declared = *length;
    std::span<const uint8_t> data;
    const nlohmann::json* meshopt = meshopt_extension(b).first;
    const bool fallback =
        meshopt && meshopt->is_object() && meshopt->value("fallback", false) == true;
    if (const auto uri = b.find("uri"); uri != b.end()) {
      if (!uri->is_string()) fail("buffer " + std::to_string(i) + " uri is not a string");
      const std::string& text = uri->get_ref<const std::string&>();
      const size_t comma = text.find(',');
      if (text.rfind("data:", 0) == 0) {
        if (comma == std::string::npos ||
            text.substr(0, comma).find(";base64") == std::string::npos)
          fail("buffer " + std::to_string(i) + " has a data: URI that is not base64");
        const std::string& decoded =
            owned_.emplace_back(decode_data_uri(std::string_view(text).substr(comma + 1), name));
        data = {reinterpret_cast<const uint8_t*>(decoded.data()), decoded.size()};
      } else {
        const std::string path = checked_resource_path(text);
        const auto bytes = file(path);
        if (!bytes) {
          if (missing.size() < 8) missing.push_back(describe_json(path));
          continue;
        }
        data = *bytes;
      }
    } else if (i == 0 && has_bin) {
      data = bin;  // read in place: the caller's bytes outlive the Document
    } else if (fallback) {
      placeholder_[i] = Empty::kMeshoptFallback;  // its views are all compressed
      buffers_.emplace_back();
      continue;
    } else {
      placeholder_[i] = Empty::kNoData;  // refused when read: nothing may need it
      buffers_.emplace_back();
      continue;
    }
    if (data.size() < declared)
      fail("buffer " + std::to_string(i) + " declares " + std::to_string(declared) +
           " bytes but holds " + std::to_string(data.size()));
    buffers_.push_back(data.first(static_cast<size_t>(declared)));
  }
  if (!missing.empty()) {
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : ", ") + m;
    throw InputError("missing_resources",
                     "the .gltf names file(s) that were not supplied: " + list +
                         (resources_ ? "; " + resources_->how_to_supply() : std::string()));
  }
}

std::optional<std::span<const uint8_t>> Document::file(const std::string& path) const {
  if (const auto known = files_.find(path); known != files_.end()) return known->second;
  if (!resources_) return std::nullopt;
  std::optional<std::string> bytes;
  try {
    bytes = resources_->fetch(path, std::min(kMaxResourceBytes, resource_budget_));
  } catch (const InputError& e) {
    if (e.check() != "too_large" || resource_budget_ >= kMaxResourceBytes) throw;
    throw InputError("too_large", "the file " + describe_json(path) +
                                      " takes the glTF's buffers and images over " +
                                      std::to_string(resource_limit_) + " bytes in all, the limit");
  }
  if (!bytes) return std::nullopt;
  charge(bytes->size(), "the file " + describe_json(path));
  const std::string& kept = owned_.emplace_back(std::move(*bytes));
  const std::span<const uint8_t> span(reinterpret_cast<const uint8_t*>(kept.data()), kept.size());
  files_.emplace(path, span);
  return span;
}

std::string Document::decode_data_uri(std::string_view base64, const std::string& what) const {
  charge(base64.size() / 4 * 3 + 3, what + "'s data: URI");  // before the bytes are made
  return decode_base64(base64, stop_);
}

void Document::charge(size_t bytes, const std::string& what) const {
  if (bytes > resource_budget_)
    throw InputError("too_large", what + " (" + std::to_string(bytes) +
                                      " bytes) takes the glTF's buffers and images over " +
                                      std::to_string(resource_limit_) +
                                      " bytes in all, the limit (each distinct source counts "
                                      "once)");
  resource_budget_ -= bytes;
}

const nlohmann::json& Document::element(const char* key, size_t index) const {
  const auto it = json_.find(key);
  const size_t count = it != json_.end() && it->is_array() ? it->size() : 0;
  const std::string noun = singular(key);
  if (index >= count)  // callers pass checked indices; said as checked_index says it
    fail("there is no " + noun + " " + std::to_string(index) + ": the file has " +
         (count == 0 ? "no " + std::string(key) : counted(count, noun, key)));
  const nlohmann::json& e = (*it)[index];
  if (!e.is_object()) fail(noun + " " + std::to_string(index) + " is not an object");
  return e;
}

size_t Document::reference(const nlohmann::json& object, const char* key, const char* array,
                           const std::string& owner) const {
  const auto it = object.find(key);
  if (it == object.end()) return SIZE_MAX;
  return checked_index(*it, array, owner + " refers to",
                       singular(array) == key ? "" : std::string(" as its ") + key);
}

size_t Document::reference(const nlohmann::json& value, const char* array,
                           const std::string& refers) const {
  return checked_index(value, array, refers, "");
}

// "bufferViews" -> "bufferView", "meshes" -> "mesh".
std::string Document::singular(const char* array) {
  std::string noun(array);
  noun.pop_back();
  if (noun == "meshe") noun.pop_back();
  return noun;
}

size_t Document::checked_index(const nlohmann::json& value, const char* array,
                               const std::string& refers, const std::string& as) const {
  const auto list = json_.find(array);
  const size_t count = list != json_.end() && list->is_array() ? list->size() : 0;
  const std::string noun = singular(array);
  const std::string named = refers + " " + noun + " " + describe_json(value) + as;
  if (!value.is_number_unsigned()) fail(named + ", which is not an index");
  if (value.get<uint64_t>() >= count)
    fail(named + ", but the file has " +
         (count == 0 ? "no " + std::string(array) : counted(count, noun, array)));
  return static_cast<size_t>(value.get<uint64_t>());
}

// The bytes `object` (a bufferView, or its meshopt compression extension) names by
// buffer, byteOffset and byteLength, checked against the buffer.
std::span<const uint8_t> Document::buffer_range(const nlohmann::json& object,
                                                const std::string& name) const {
  const size_t buffer = reference(object, "buffer", "buffers", name);
  if (buffer == SIZE_MAX) fail(name + " has no buffer");
  const uint64_t available = buffers_[buffer].size();
  const std::string within = "(an integer from 0 to " + std::to_string(available) +
                             ", the size of buffer " + std::to_string(buffer) + ")";
  const uint64_t offset =
      whole_field(object, "byteOffset", name, "a byte offset " + within).value_or(0);
  const std::optional<uint64_t> length =
      whole_field(object, "byteLength", name, "a byte count " + within);
  if (!length) fail(name + " has no byteLength");
  if (placeholder_[buffer] == Empty::kMeshoptFallback)
    fail(name + " reads buffer " + std::to_string(buffer) +
         ", which only stands in for meshopt-compressed data and holds none");
  if (placeholder_[buffer] == Empty::kNoData)
    fail(name + " reads buffer " + std::to_string(buffer) +
         ", which has no data (no uri and no GLB binary chunk)");
  if (offset > available || *length > available - offset)
    fail(name + " (bytes " + std::to_string(offset) + "+" + std::to_string(*length) +
         ") runs past its buffer of " + std::to_string(available) + " bytes");
  return buffers_[buffer].subspan(offset, *length);
}

std::span<const uint8_t> Document::buffer_view(size_t index) const {
  const nlohmann::json& view = element("bufferViews", index);
  const std::string name = "bufferView " + std::to_string(index);
  const auto [extension, extension_name] = meshopt_extension(view);
  if (!extension) return buffer_range(view, name);
  if (const auto done = decoded_views_.find(index); done != decoded_views_.end())
    return done->second;
  const nlohmann::json& meshopt = *extension;
  if (!meshopt.is_object()) fail(name + ": " + extension_name + " is not an object");
  const std::optional<uint64_t> length =
      whole_field(view, "byteLength", name, "a byte count (a non-negative integer)");
  if (!length) fail(name + " has no byteLength");
  std::vector<uint8_t> decoded =
      decode_meshopt_view(meshopt, extension_name, buffer_range(meshopt, name + " (compressed)"),
                          *length, decode_budget_, index);
  decode_budget_ -= decoded.size();
  return decoded_views_.emplace(index, std::move(decoded)).first->second;
}

Document::AccessorView Document::accessor(size_t index) const {
  const nlohmann::json& a = element("accessors", index);
  const std::string name = "accessor " + std::to_string(index);
  const auto sparse = a.find("sparse");
  const size_t view_index = reference(a, "bufferView", "bufferViews", name);
  AccessorView v;
  const std::optional<uint64_t> type =
      whole_field(a, "componentType", name, "a componentType (5120 to 5126)");
  if (!type) fail(name + " has no componentType");
  const size_t csize = *type <= 5126 ? component_size(static_cast<int>(*type)) : 0;
  if (csize == 0)
    fail(name + "'s componentType " + std::to_string(*type) +
         " is not one glTF defines (5120 to 5123, 5125, 5126)");
  v.component_type = static_cast<int>(*type);
  if (!a.contains("type") || !a["type"].is_string()) fail(name + " has no type");
  v.components = component_count(a["type"].get<std::string>());
  if (v.components == 0) fail(name + " has an unknown type");
  const std::optional<uint64_t> count =
      whole_field(a, "count", name, "an element count (a non-negative integer)");
  if (!count) fail(name + " has no count");
  v.count = *count;
  v.element_size = csize * static_cast<size_t>(v.components);
  v.stride = v.element_size;
  if (view_index != SIZE_MAX) {
    const nlohmann::json& view = element("bufferViews", view_index);
    // 0 too (see below); glTF's 4 to 252 is otherwise checked against the element size.
    v.stride =
        range_field(view, "byteStride", 0, 252,
                    "bufferView " + std::to_string(view_index) + "'s byteStride", v.element_size);
    // byteStride 0 is outside the spec (4..252, and none on index views), but exporters
    // write it for "packed" and viewers read it so: here too, said once per view.
    if (v.stride == 0) {
      v.stride = v.element_size;
      if (std::find(zero_stride_views_.begin(), zero_stride_views_.end(), view_index) ==
          zero_stride_views_.end())
        zero_stride_views_.push_back(view_index);
    }
    if (v.stride < v.element_size) fail(name + " elements overlap (byteStride too small)");
    const std::span<const uint8_t> bytes = buffer_view(view_index);
    const uint64_t offset =
        whole_field(a, "byteOffset", name,
                    "a byte offset (an integer from 0 to " + std::to_string(bytes.size()) +
                        ", the size of bufferView " + std::to_string(view_index) + ")")
            .value_or(0);
    // Checked in 64 bits, and count first bounded by the bytes present: no overflow.
    if (v.count > 0 &&
        (offset > bytes.size() || (v.count - 1) > (bytes.size() - offset) / v.stride ||
         offset + (v.count - 1) * v.stride + v.element_size > bytes.size()))
      fail(name + " (" + std::to_string(v.count) + " elements) runs past its bufferView of " +
           std::to_string(bytes.size()) + " bytes");
    v.bytes = v.count > 0 ? bytes.subspan(offset) : std::span<const uint8_t>{};
  }
  // Without a bufferView the elements are zeros (glTF 3.6.2.3), a sparse accessor's
  // other elements too.
  if (sparse == a.end()) return view_index == SIZE_MAX ? zero_filled(index, v, name) : v;
  return with_sparse(index, v, *sparse, name);
}

// An accessor without a bufferView or sparse (valid glTF: glTF-Validator's
// KHR_mesh_quantization valid.gltf was refused "accessor 0 has no bufferView"): `count`
// zero elements, made once and charged to the decode budget, since no bytes bound `count`.
Document::AccessorView Document::zero_filled(size_t index, AccessorView v,
                                             const std::string& name) const {
  auto done = sparse_accessors_.find(index);
  if (done == sparse_accessors_.end()) {
    if (v.count > decode_budget_ / v.element_size)
      throw InputError("too_large", name + ": its " + std::to_string(v.count) +
                                        " elements (zeros: it has no bufferView) take the " +
                                        "decoded bytes over the limit");
    done = sparse_accessors_.emplace(index, std::vector<uint8_t>(v.count * v.element_size)).first;
    decode_budget_ -= done->second.size();
  }
  v.bytes = done->second;
  v.stride = v.element_size;
  return v;
}

// The bytes of `sparse`'s indices or values: `count` elements of `size` bytes from its
// bufferView (no stride) at its byteOffset, checked against the view.
std::span<const uint8_t> Document::sparse_part(const nlohmann::json& part, size_t count,
                                               size_t size, const std::string& name) const {
  if (!part.is_object()) fail(name + " is not an object");
  const size_t view = reference(part, "bufferView", "bufferViews", name);
  if (view == SIZE_MAX) fail(name + " has no bufferView");
  const std::span<const uint8_t> bytes = buffer_view(view);
  const uint64_t offset =
      whole_field(part, "byteOffset", name,
                  "a byte offset (an integer from 0 to " + std::to_string(bytes.size()) +
                      ", the size of bufferView " + std::to_string(view) + ")")
          .value_or(0);
  if (offset > bytes.size() || count > (bytes.size() - offset) / size)
    fail(name + " (" + std::to_string(count) + " elements) runs past its bufferView of " +
         std::to_string(bytes.size()) + " bytes");
  return bytes.subspan(offset, count * size);
}

// A sparse accessor (KhronosGroup's SimpleSparseAccessor; morph targets and edited
// exports): the dense elements, each listed index's element replaced, made once per
// accessor and charged to the decode budget before anything is allocated.
Document::AccessorView Document::with_sparse(size_t index, AccessorView v,
                                             const nlohmann::json& sparse,
                                             const std::string& name) const {
  auto dense_view = [&](const std::vector<uint8_t>& dense) {
    v.bytes = dense;
    v.stride = v.element_size;
    return v;
  };
  if (const auto done = sparse_accessors_.find(index); done != sparse_accessors_.end())
    return dense_view(done->second);
  if (!sparse.is_object()) fail(name + ": sparse is not an object");
  // Compared, not bounded by v.count + 1: that overflows for a count of 2^64 - 1.
  const std::optional<uint64_t> declared =
      whole_field(sparse, "count", name + "'s sparse", "an element count (a non-negative integer)");
  if (!declared) fail(name + ": sparse has no count");
  if (*declared == 0 || *declared > v.count)
    fail(name + "'s sparse.count " + std::to_string(*declared) + " is not an integer from 1 to " +
         std::to_string(v.count) + " (its count)");
  const size_t count = static_cast<size_t>(*declared);
  if (!sparse.contains("indices") || !sparse.contains("values"))
    fail(name + ": sparse needs indices and values");
  const nlohmann::json& indices = sparse["indices"];
  const nlohmann::json* type = indices.is_object() && indices.contains("componentType")
                                   ? &indices["componentType"]
                                   : nullptr;
  const int index_type = type && type->is_number_unsigned() && type->get<uint64_t>() <= 5125
                             ? static_cast<int>(type->get<uint64_t>())
                             : 0;
  if (index_type != 5121 && index_type != 5123 && index_type != 5125)
    fail(name + ": sparse indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT (5121, " +
         "5123 or 5125), not " + (type ? describe_json(*type) : std::string("none")));
  const size_t index_size = component_size(index_type);
  const std::span<const uint8_t> where =
      sparse_part(indices, count, index_size, name + ": sparse.indices");
  const std::span<const uint8_t> values =
      sparse_part(sparse["values"], count, v.element_size, name + ": sparse.values");
  if (v.count > decode_budget_ / v.element_size)
    throw InputError("too_large", name + ": its " + std::to_string(v.count) +
                                      " sparse elements take the decoded bytes over " +
                                      "the limit");
  std::vector<uint8_t> dense(v.count * v.element_size);  // zeros without a bufferView
  decode_budget_ -= dense.size();
  for (size_t i = 0; i < v.count && !v.bytes.empty(); ++i) {
    stop_.tick();
    std::memcpy(dense.data() + i * v.element_size, v.bytes.data() + i * v.stride, v.element_size);
  }
  size_t previous = 0;
  for (size_t k = 0; k < count; ++k) {
    stop_.tick();
    uint32_t at = 0;
    const uint8_t* p = where.data() + k * index_size;
    if (index_type == 5121)
      at = p[0];
    else if (index_type == 5123)
      at = static_cast<uint32_t>(p[0] | p[1] << 8);
    else
      std::memcpy(&at, p, 4);
    if (at >= v.count || (k > 0 && at <= previous))
      fail(name + ": sparse index " + std::to_string(at) + " at position " + std::to_string(k) +
           " is out of range or not increasing (" + std::to_string(v.count) + " elements)");
    previous = at;
    std::memcpy(dense.data() + size_t{at} * v.element_size, values.data() + k * v.element_size,
                v.element_size);
  }
  return dense_view(sparse_accessors_.emplace(index, std::move(dense)).first->second);
}

std::vector<std::string> Document::warnings() const {
  std::vector<std::string> out;
  if (read_as_gltf1_)
    out.push_back(
        "read as glTF 1.0: its geometry, node transforms and diffuse colours and textures; "
        "its shaders, animations and skins are not read");
  if (uses_extension(kShaderExtension))
    out.push_back(std::string("the file's ") + kShaderExtension +
                  " shaders are not run: its geometry is read as stored");
  if (zero_stride_views_.empty()) return out;
  // One sentence however many views: a file may have thousands.
  std::vector<size_t> views = zero_stride_views_;
  std::sort(views.begin(), views.end());
  std::string list;
  for (size_t i = 0; i < views.size() && i < 8; ++i)
    list += (i ? ", " : "") + std::to_string(views[i]);
  if (views.size() > 8) list += ", ...";
  out.push_back("byteStride 0 (not valid glTF) read as tightly packed in " +
                std::to_string(views.size()) + " bufferView" + (views.size() > 1 ? "s" : "") +
                " (" + list + ")");
  return out;
}

// One component of an accessor element as a double: FLOAT as it is, normalized integers
// to [-1, 1] or [0, 1] (signed ones clamped at -1), other integers as they are.
static double component_value(const uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case 5120: {
      const double x = static_cast<int8_t>(p[0]);
      return normalized ? std::max(x / 127.0, -1.0) : x;
    }
    case 5121:
      return normalized ? p[0] / 255.0 : p[0];
    case 5122: {
      int16_t x;
      std::memcpy(&x, p, 2);
      return normalized ? std::max(x / 32767.0, -1.0) : x;
    }
    case 5123: {
      uint16_t x;
      std::memcpy(&x, p, 2);
      return normalized ? x / 65535.0 : x;
    }
    case 5125: {
      uint32_t x;
      std::memcpy(&x, p, 4);
      return normalized ? x / 4294967295.0 : x;
    }
    default: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
  }
}

std::vector<double> Document::read_numbers(const AccessorView& v, size_t index) const {
  const nlohmann::json& a = element("accessors", index);
  const bool normalized = a.contains("normalized") && a["normalized"] == true;
  const size_t size = component_size(v.component_type);
  const size_t components = static_cast<size_t>(v.components);
  std::vector<double> out(v.count * components);
  for (size_t i = 0; i < v.count; ++i) {
    stop_.tick(components);
    for (size_t c = 0; c < components; ++c)
      out[i * components + c] =
          component_value(v.bytes.data() + i * v.stride + size * c, v.component_type, normalized);
  }
  return out;
}

std::vector<double> Document::read_positions(size_t index) const {
  const AccessorView v = accessor(index);
  const std::string name = "POSITION accessor " + std::to_string(index);
  if (v.components != 3) fail(name + " must be VEC3");
  const bool quantized = v.component_type != 5126;
  if (quantized && v.component_type == 5125)
    fail(name +
         " is UNSIGNED_INT; positions are FLOAT or, with KHR_mesh_quantization, "
         "(UNSIGNED_)BYTE or (UNSIGNED_)SHORT");
  if (quantized && !uses_extension("KHR_mesh_quantization"))
    fail(name +
         " stores integers, which needs KHR_mesh_quantization, and the file does not "
         "list that extension in extensionsUsed");
  // KHR_mesh_quantization: unnormalized integers are taken as they are; the node
  // transform scales them.
  return read_numbers(v, index);
}

Document::AccessorShape Document::accessor_shape(size_t index) const {
  const AccessorView v = accessor(index);
  const nlohmann::json& a = element("accessors", index);
  return {v.count, v.components, v.component_type,
          a.contains("normalized") && a["normalized"] == true};
}

std::vector<double> Document::read_attribute(size_t index, int* components) const {
  const AccessorView v = accessor(index);
  *components = v.components;
  return read_numbers(v, index);
}

std::optional<std::string> Document::image_bytes(size_t index) const {
  const nlohmann::json& image = element("images", index);
  if (const size_t view =
          reference(image, "bufferView", "bufferViews", "image " + std::to_string(index));
      view != SIZE_MAX) {
    const std::span<const uint8_t> bytes = buffer_view(view);
    charge(bytes.size(), "image " + std::to_string(index));
    return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  }
  const auto uri = image.find("uri");
  if (uri == image.end() || !uri->is_string()) return std::nullopt;
  const std::string& text = uri->get_ref<const std::string&>();
  if (text.rfind("data:", 0) == 0) {
    const size_t comma = text.find(',');
    if (comma == std::string::npos || text.substr(0, comma).find(";base64") == std::string::npos)
      return std::nullopt;
    return decode_data_uri(std::string_view(text).substr(comma + 1),
                           "image " + std::to_string(index));
  }
  const auto bytes = file(checked_resource_path(text));
  if (!bytes) return std::nullopt;
  charge(bytes->size(), "image " + std::to_string(index));
  return std::string(reinterpret_cast<const char*>(bytes->data()), bytes->size());
}

std::vector<uint32_t> Document::read_indices(size_t index, size_t vertex_count) const {
  const AccessorView v = accessor(index);
  if (v.components != 1 ||
      (v.component_type != 5121 && v.component_type != 5123 && v.component_type != 5125))
    fail("index accessor " + std::to_string(index) + " must be an unsigned SCALAR");
  std::vector<uint32_t> out(v.count);
  for (size_t i = 0; i < v.count; ++i) {
    stop_.tick();
    const uint8_t* p = v.bytes.data() + i * v.stride;
    uint32_t value = 0;
    if (v.component_type == 5121)
      value = p[0];
    else if (v.component_type == 5123)
      value = static_cast<uint32_t>(p[0] | p[1] << 8);
    else
      std::memcpy(&value, p, 4);
    if (value >= vertex_count)
      fail("index " + std::to_string(value) + " at position " + std::to_string(i) +
           " of accessor " + std::to_string(index) + " is past the " +
           std::to_string(vertex_count) + " vertices");
    out[i] = value;
  }
  return out;
}

}  // namespace spheremap::gltf
