// Decoding the PNG and JPEG images a glTF carries (libpng, libjpeg-turbo), to 8-bit RGBA.
// Input is untrusted: the size is read from the header and checked against a pixel cap
// before any pixel is decoded.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spheremap {

struct RgbaImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // row-major, top row first, 4 bytes a pixel
};

// The type its first bytes say: "image/png", "image/jpeg", "image/webp", "image/ktx2", or
// "" when none of these.
std::string image_type(std::string_view bytes);

// The width x height a PNG's or JPEG's header declares, without decoding a pixel; 0 when
// it is neither or its header does not read.
size_t image_pixels(std::string_view bytes);

// The image, or nothing when it is not a PNG or JPEG that decodes, or has more than
// `max_pixels` pixels. Throws InputError("jpeg_scans") for a JPEG of more than
// kMaxJpegScans scans (core/io/jpeg_scans.h), before decoding any.
std::optional<RgbaImage> decode_image(std::string_view bytes, size_t max_pixels);

}  // namespace spheremap
