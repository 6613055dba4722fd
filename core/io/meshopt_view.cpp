#include "core/io/meshopt_view.h"

#include <meshoptimizer.h>

#include <string>

#include "core/io/gltf_document.h"
#include "core/mesh/input_error.h"

namespace spheremap::gltf {
namespace {

// Bytes of output per byte of input at most, with a margin: the vertex codec spends at
// least 2 bits on a group of 16 bytes (64:1), the index codecs at least a byte per
// triangle or index.
constexpr size_t kMaxExpansion = 80;
constexpr size_t kExpansionSlack = 64 * 1024;

// The vertex codec's first byte: 0xa0 | version. meshoptimizer 0.18 decodes version 0.
constexpr uint8_t kVertexHeader = 0xa0;

// "0.18" for the meshoptimizer this build uses (MESHOPTIMIZER_VERSION 180).
std::string library_version() {
  return std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
         std::to_string(MESHOPTIMIZER_VERSION % 1000 / 10);
}

std::string text_field(const nlohmann::json& object, const std::string& name, const char* key,
                       const char* fallback) {
  const auto it = object.find(key);
  if (it == object.end()) return fallback;
  if (!it->is_string()) fail(name + " " + key + " is not a string");
  return it->get<std::string>();
}

}  // namespace

std::vector<uint8_t> decode_meshopt_view(const nlohmann::json& extension,
                                         const char* extension_name,
                                         std::span<const uint8_t> compressed, size_t view_length,
                                         size_t max_bytes, size_t view_index) {
  const std::string name = "bufferView " + std::to_string(view_index) + " (" + extension_name + ")";
  const std::optional<uint64_t> declared =
      whole_field(extension, "count", name, "an element count (a non-negative integer)");
  const size_t stride = range_field(extension, "byteStride", 1, 256, name + "'s byteStride");
  if (!declared || stride == SIZE_MAX) fail(name + " needs count and byteStride");
  const size_t count = *declared;
  const std::string mode = text_field(extension, name, "mode", "");
  const std::string filter = text_field(extension, name, "filter", "NONE");
  if (count > max_bytes / stride)
    throw InputError("too_large", name + " decodes to " + std::to_string(count) + " x " +
                                      std::to_string(stride) + " bytes, over the limit of " +
                                      std::to_string(max_bytes));
  const size_t size = count * stride;
  if (size > compressed.size() * kMaxExpansion + kExpansionSlack)
    fail(name + " declares " + std::to_string(size) + " bytes from " +
         std::to_string(compressed.size()) + " compressed bytes, more than the codec can hold");
  if (size != view_length)
    fail(name + " decodes to " + std::to_string(size) + " bytes but the view declares " +
         std::to_string(view_length));
  std::vector<uint8_t> out(size);
  int status = -1;
  if (mode == "ATTRIBUTES") {
    if (stride % 4 != 0) fail(name + ": ATTRIBUTES need a byteStride that is a multiple of 4");
    if (!compressed.empty() && (compressed[0] & 0xf0) == kVertexHeader &&
        compressed[0] != kVertexHeader)
      fail(name + " is encoded with version " + std::to_string(compressed[0] & 0x0f) +
           " of meshoptimizer's vertex codec; the meshoptimizer this build uses (Debian's " +
           library_version() + ") decodes version 0 only");
    status =
        meshopt_decodeVertexBuffer(out.data(), count, stride, compressed.data(), compressed.size());
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4) fail(name + ": indices need a byteStride of 2 or 4");
    if (mode == "TRIANGLES" && count % 3 != 0)
      fail(name + ": TRIANGLES need a count that is a multiple of 3");
    status = mode == "TRIANGLES"
                 ? meshopt_decodeIndexBuffer(out.data(), count, stride, compressed.data(),
                                             compressed.size())
                 : meshopt_decodeIndexSequence(out.data(), count, stride, compressed.data(),
                                               compressed.size());
  } else {
    fail(name + " has mode '" + mode.substr(0, 20) +
         "'; ATTRIBUTES, TRIANGLES or INDICES expected");
  }
  if (status != 0)
    fail(name + " does not decode (meshoptimizer error " + std::to_string(status) + ")");
  if (filter == "OCTAHEDRAL" || filter == "QUATERNION") {
    if (mode != "ATTRIBUTES" || (stride != 4 && stride != 8) ||
        (filter == "QUATERNION" && stride != 8))
      fail(name + ": the " + filter + " filter needs ATTRIBUTES of 4 or 8 bytes");
    filter == "OCTAHEDRAL" ? meshopt_decodeFilterOct(out.data(), count, stride)
                           : meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (filter == "EXPONENTIAL") {
    if (mode != "ATTRIBUTES") fail(name + ": the EXPONENTIAL filter needs ATTRIBUTES");
    meshopt_decodeFilterExp(out.data(), count, stride);
  } else if (filter == "COLOR" && std::string(extension_name) == "KHR_meshopt_compression") {
    fail(name + " uses the COLOR filter, which the meshoptimizer this build uses (Debian's " +
         library_version() + ") does not decode");
  } else if (filter != "NONE") {
    fail(name + " has filter '" + filter.substr(0, 20) +
         "'; NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL expected");
  }
  return out;
}

}  // namespace spheremap::gltf
