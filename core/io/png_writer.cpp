#include "core/io/png_writer.h"

#include <zlib.h>

#include <stdexcept>
#include <vector>

namespace spheremap {
namespace {

void append_u32_be(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<char>((v >> shift) & 0xff));
}

void append_chunk(std::string& out, const char type[4], const std::string& data) {
  append_u32_be(out, static_cast<uint32_t>(data.size()));
  const size_t start = out.size();
  out.append(type, 4);
  out += data;
  const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(out.data() + start),
                          static_cast<uInt>(out.size() - start));
  append_u32_be(out, static_cast<uint32_t>(crc));
}

}  // namespace

std::string encode_png(int width, int height, int bit_depth, std::span<const uint16_t> rgb) {
  if ((bit_depth != 8 && bit_depth != 16) || width <= 0 || height <= 0 ||
      rgb.size() != static_cast<size_t>(width) * height * 3)
    throw std::invalid_argument("encode_png: bad image size or bit depth");
  const size_t bytes_per_sample = bit_depth / 8;
  std::vector<Bytef> raw;
  raw.reserve(static_cast<size_t>(height) * (1 + width * 3 * bytes_per_sample));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    for (int k = 0; k < width * 3; ++k) {
      const uint16_t v = rgb[static_cast<size_t>(y) * width * 3 + k];
      if (bit_depth == 16) raw.push_back(static_cast<Bytef>(v >> 8));
      raw.push_back(static_cast<Bytef>(v & 0xff));
    }
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, raw.data(),
                static_cast<uLong>(raw.size()), 6) != Z_OK)
    throw std::runtime_error("encode_png: zlib failed");
  packed.resize(packed_size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  append_u32_be(header, static_cast<uint32_t>(width));
  append_u32_be(header, static_cast<uint32_t>(height));
  header += {static_cast<char>(bit_depth), 2 /* RGB */, 0, 0, 0};
  append_chunk(png, "IHDR", header);
  append_chunk(png, "IDAT", packed);
  append_chunk(png, "IEND", "");
  return png;
}

}  // namespace spheremap
