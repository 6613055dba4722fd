// The checked pieces of a glTF file: its JSON and its buffers, with typed, bounds-checked
// access to accessors. Internal to the glTF reader.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

namespace spheremap::gltf {

[[noreturn]] void fail(const std::string& message);

class Document {
 public:
  // bytes: a GLB file or glTF JSON text.
  explicit Document(std::span<const uint8_t> bytes);

  const nlohmann::json& json() const { return json_; }
  // The bytes of bufferView `index`, checked against its buffer.
  std::span<const uint8_t> buffer_view(size_t index) const;
  // Accessor `index` read as doubles (positions) or indices, checked against its view.
  std::vector<double> read_floats(size_t index, int components) const;
  std::vector<uint32_t> read_indices(size_t index, size_t vertex_count) const;

  // Array element `index` of json()[key], or fail naming the reference.
  const nlohmann::json& element(const char* key, size_t index) const;

 private:
  struct AccessorView {
    std::span<const uint8_t> bytes;
    size_t count, stride, element_size;
    int component_type, components;
  };
  AccessorView accessor(size_t index) const;
  void load_buffers(std::span<const uint8_t> bin_chunk, bool has_bin);

  nlohmann::json json_;
  std::vector<std::vector<uint8_t>> buffers_;
};

// Integer field of a JSON object: absent -> fallback; present but not a non-negative
// integer below `limit` -> fail naming `what`.
size_t index_field(const nlohmann::json& object, const char* key, size_t limit, const char* what,
                   size_t fallback = SIZE_MAX);

}  // namespace spheremap::gltf
