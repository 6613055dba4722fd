// EXT_meshopt_compression and KHR_meshopt_compression: the bytes of one compressed
// bufferView, decoded with meshoptimizer's own decoders (Debian libmeshoptimizer-dev).
// Internal to the glTF reader. The Khronos extension allows two things the vendor one does
// not: version 1 of the vertex codec and the COLOR filter; meshoptimizer 0.18 (Debian 12)
// decodes neither, so such views are refused by name, and the rest decode as under EXT.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

namespace spheremap::gltf {

// `extension` is the bufferView's meshopt compression object (`extension_name`: which of
// the two, for messages) and `compressed` the bytes it points at (already checked against
// their buffer). The decoded size,
// count x byteStride, is checked before any allocation against `max_bytes` and against
// what `compressed` can expand to (meshoptimizer's codecs shrink at most 64:1); a stream
// that does not decode, or decodes to a different size than `view_length`, is refused
// with InputError("gltf").
std::vector<uint8_t> decode_meshopt_view(const nlohmann::json& extension,
                                         const char* extension_name,
                                         std::span<const uint8_t> compressed, size_t view_length,
                                         size_t max_bytes, size_t view_index);

}  // namespace spheremap::gltf
