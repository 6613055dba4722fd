// A minimal PNG encoder (RGB, 8 or 16 bits per channel, zlib from Debian) for the
// geometry image and the checker texture.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace spheremap {

// `rgb`: width * height * 3 samples, rows top to bottom, each below 2^bit_depth.
// bit_depth: 8 or 16.
std::string encode_png(int width, int height, int bit_depth, std::span<const uint16_t> rgb);

}  // namespace spheremap
