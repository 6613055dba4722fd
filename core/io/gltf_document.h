// The checked pieces of a glTF file: its JSON and its buffers, with typed, bounds-checked
// access to accessors. Internal to the glTF reader.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/io/gltf_resources.h"

namespace spheremap::gltf {

[[noreturn]] void fail(const std::string& message);

// An extension of materials and textures only (KHR_materials_*, texture transforms and
// image formats): what outputs that keep the input's materials may keep.
bool material_extension(const std::string& name);

class Document {
 public:
  // bytes: a GLB file or glTF JSON text. `resources` supplies the files that buffer URIs
  // name (none: every such URI is reported missing). EXT_meshopt_compression views decode
  // to at most `max_decoded_bytes` in all. Checks extensionsRequired first: an extension
  // that changes geometry and is not read here is refused by name.
  Document(std::span<const uint8_t> bytes, const GltfResources* resources,
           size_t max_decoded_bytes);

  const nlohmann::json& json() const { return json_; }
  // The bytes of bufferView `index`, checked against its buffer.
  std::span<const uint8_t> buffer_view(size_t index) const;
  // Accessor `index` read as doubles (positions: FLOAT, or the integer types of
  // KHR_mesh_quantization, normalized or not) or indices, checked against its view.
  std::vector<double> read_positions(size_t index) const;
  std::vector<uint32_t> read_indices(size_t index, size_t vertex_count) const;
  // Any accessor as doubles (normalized integers scaled to [0, 1] or [-1, 1]), `components`
  // per element, which is set.
  std::vector<double> read_attribute(size_t index, int* components) const;
  // The encoded bytes of image `index` (its bufferView, data: URI or file from the
  // resources), or nothing when they are not available.
  std::optional<std::string> image_bytes(size_t index) const;

  // Array element `index` of json()[key], or fail naming the reference.
  const nlohmann::json& element(const char* key, size_t index) const;

  // What was read leniently (bufferViews with byteStride 0 read as tightly packed, as
  // viewers do), one sentence per kind, for the report.
  std::vector<std::string> warnings() const;

 private:
  struct AccessorView {
    std::span<const uint8_t> bytes;
    size_t count, stride, element_size;
    int component_type, components;
  };
  AccessorView accessor(size_t index) const;
  std::vector<double> read_numbers(const AccessorView& view, size_t index) const;
  void check_required_extensions() const;
  void load_buffers(std::span<const uint8_t> bin_chunk, bool has_bin,
                    const GltfResources* resources);
  std::span<const uint8_t> buffer_range(const nlohmann::json& object, size_t buffer_limit,
                                        const std::string& name) const;
  bool uses_extension(const char* name) const;

  nlohmann::json json_;
  const GltfResources* resources_;  // lives as long as the Document (read_gltf's caller)
  std::vector<std::vector<uint8_t>> buffers_;
  // Buffers that only stand in for EXT_meshopt_compression data ("fallback": true, no uri).
  std::vector<char> placeholder_;
  // Decoded EXT_meshopt_compression views, by view index, and the bytes left to decode.
  mutable std::map<size_t, std::vector<uint8_t>> decoded_views_;
  mutable size_t decode_budget_;
  mutable std::vector<size_t> zero_stride_views_;  // read as packed, each once
};

// Integer field of a JSON object: absent -> fallback; present but not a non-negative
// integer below `limit` -> fail naming `what`.
size_t index_field(const nlohmann::json& object, const char* key, size_t limit, const char* what,
                   size_t fallback = SIZE_MAX);

}  // namespace spheremap::gltf
