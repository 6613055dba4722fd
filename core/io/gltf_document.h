// The checked pieces of a glTF file: its JSON and its buffers, with typed, bounds-checked
// access to accessors. Internal to the glTF reader.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/io/gltf_resources.h"
#include "core/mesh/stop_check.h"

namespace spheremap::gltf {

[[noreturn]] void fail(const std::string& message);

// An extension of materials and textures only (KHR_materials_*, texture transforms and
// image formats): what outputs that keep the input's materials may keep.
bool material_extension(const std::string& name);

struct DocumentLimits {
  size_t max_decoded_bytes = SIZE_MAX;   // EXT_meshopt_compression views decoded, in all
  size_t max_resource_bytes = SIZE_MAX;  // buffers and images held, in all
  const std::function<bool()>* should_stop = nullptr;  // see GltfReadOptions
};

class Document {
 public:
  // bytes: a GLB file or glTF JSON text, which must outlive the Document (its binary
  // chunk is read in place). `resources` supplies the files that URIs name (none: every
  // such URI is reported missing); each file is fetched once however many buffers name
  // it. Checks extensionsRequired first: an extension that changes geometry and is not
  // read here is refused by name.
  Document(std::span<const uint8_t> bytes, const GltfResources* resources,
           const DocumentLimits& limits);

  const nlohmann::json& json() const { return json_; }
  // The file was glTF 1.0 and json() is its 2.0 upgrade (gltf1_upgrade.h).
  bool read_as_gltf1() const { return read_as_gltf1_; }
  // The bytes of bufferView `index`, checked against its buffer.
  std::span<const uint8_t> buffer_view(size_t index) const;
  // Accessor `index` read as doubles (positions: FLOAT, or the integer types of
  // KHR_mesh_quantization, normalized or not) or indices, checked against its view.
  std::vector<double> read_positions(size_t index) const;
  std::vector<uint32_t> read_indices(size_t index, size_t vertex_count) const;
  // Any accessor as doubles (normalized integers scaled to [0, 1] or [-1, 1]), `components`
  // per element, which is set.
  std::vector<double> read_attribute(size_t index, int* components) const;
  // Accessor `index`'s declared count, type's components and componentType, checked
  // against its view but not decoded: what a caller checks before it decodes.
  struct AccessorShape {
    size_t count;
    int components, component_type;
    bool normalized;
  };
  AccessorShape accessor_shape(size_t index) const;
  // The encoded bytes of image `index` (its bufferView, data: URI or file from the
  // resources), or nothing when they are not available. Charged to max_resource_bytes.
  std::optional<std::string> image_bytes(size_t index) const;
  // Asks the stop callback every few thousand calls (see StopCheck).
  void tick(size_t elements = 1) const { stop_.tick(elements); }

  // Array element `index` of json()[key], or fail naming the reference.
  const nlohmann::json& element(const char* key, size_t index) const;
  // The index `object[key]` holds into json()[array], SIZE_MAX when absent. One that is not
  // an index or is past the array's end fails where it is resolved, saying so, e.g.
  // "accessor 0 refers to bufferView 5, but the file has 1 bufferView" (never "missing").
  size_t reference(const nlohmann::json& object, const char* key, const char* array,
                   const std::string& owner) const;
  // The same check of `value`, an index into json()[array] listed by its referrer:
  // `refers` is the start of the sentence, e.g. "node 2's children refer to", giving
  // "node 2's children refer to node 5, but the file has 3 nodes".
  size_t reference(const nlohmann::json& value, const char* array, const std::string& refers) const;

  // What was read leniently (bufferViews with byteStride 0 read as tightly packed, as
  // viewers do), one sentence per kind, for the report.
  std::vector<std::string> warnings() const;

 private:
  static std::string singular(const char* array);
  // reference()'s check: `refers` + " node 5" + `as` + ", but the file has ...".
  size_t checked_index(const nlohmann::json& value, const char* array, const std::string& refers,
                       const std::string& as) const;
  struct AccessorView {
    std::span<const uint8_t> bytes;
    size_t count, stride, element_size;
    int component_type, components;
  };
  AccessorView accessor(size_t index) const;
  AccessorView with_sparse(size_t index, AccessorView dense, const nlohmann::json& sparse,
                           const std::string& name) const;
  AccessorView zero_filled(size_t index, AccessorView v, const std::string& name) const;
  std::span<const uint8_t> sparse_part(const nlohmann::json& part, size_t count, size_t size,
                                       const std::string& name) const;
  std::vector<double> read_numbers(const AccessorView& view, size_t index) const;
  void check_required_extensions() const;
  void load_buffers(std::span<const uint8_t> bin_chunk, bool has_bin);
  std::span<const uint8_t> buffer_range(const nlohmann::json& object,
                                        const std::string& name) const;
  bool uses_extension(const char* name) const;
  // The file at `path` from the resources, fetched once and kept; nothing when missing.
  std::optional<std::span<const uint8_t>> file(const std::string& path) const;
  // A data: URI's bytes, decoded (and charged) here.
  std::string decode_data_uri(std::string_view base64, const std::string& what) const;
  // Takes `bytes` from the resource budget, or throws InputError("too_large").
  void charge(size_t bytes, const std::string& what) const;

  nlohmann::json json_;
  bool read_as_gltf1_ = false;      // json_ is the 2.0 upgrade of a glTF 1.0 file
  const GltfResources* resources_;  // lives as long as the Document (read_gltf's caller)
  // Per buffer, its bytes: in the GLB's binary chunk, or in `owned_` (decoded data:
  // URIs, fetched files). Buffers naming one file share its one copy.
  std::vector<std::span<const uint8_t>> buffers_;
  mutable std::deque<std::string> owned_;  // a deque: spans into it stay valid
  mutable std::map<std::string, std::span<const uint8_t>> files_;
  size_t resource_limit_;
  mutable size_t resource_budget_;
  mutable StopCheck stop_;
  // Buffers that hold no bytes, and why; refused only when something reads them, so a
  // file whose meshes do not need them (or that has no meshes) gets the real complaint.
  enum class Empty : char { kNo, kMeshoptFallback, kNoData };
  std::vector<Empty> placeholder_;
  // Decoded EXT_meshopt_compression views, by view index, and the bytes left to decode.
  mutable std::map<size_t, std::vector<uint8_t>> decoded_views_;
  mutable size_t decode_budget_;
  // Sparse accessors made dense, and accessors without a bufferView made of zeros, by
  // accessor index (charged to decode_budget_).
  mutable std::map<size_t, std::vector<uint8_t>> sparse_accessors_;
  mutable std::vector<size_t> zero_stride_views_;  // read as packed, each once
};

// Integer field of a JSON object bounded by the spec (not by a count of things in the file:
// those are reference()s): absent -> fallback; present but not an integer from `min` to
// `max` -> fail naming `what` and that range.
size_t range_field(const nlohmann::json& object, const char* key, uint64_t min, uint64_t max,
                   const std::string& what, size_t fallback = SIZE_MAX);

// A count, byte offset or byte length: absent -> nullopt; present but not a non-negative
// integer -> fail "<owner>'s <key> <value> is not <expected>", where `expected` says the
// real bound (e.g. "a byte count (an integer from 0 to 44, the size of buffer 0)"). The
// caller checks the range against the bytes it has.
std::optional<uint64_t> whole_field(const nlohmann::json& object, const char* key,
                                    const std::string& owner, const std::string& expected);

}  // namespace spheremap::gltf
