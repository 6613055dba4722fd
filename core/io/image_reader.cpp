#include "core/io/image_reader.h"

#include <png.h>
#include <turbojpeg.h>

#include <memory>
#include <string>

#include "core/io/jpeg_scans.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

std::optional<RgbaImage> decode_png(std::string_view bytes, size_t max_pixels) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return std::nullopt;
  if (image.width == 0 || image.height == 0 ||
      static_cast<uint64_t>(image.width) * image.height > max_pixels) {
    png_image_free(&image);
    return std::nullopt;
  }
  image.format = PNG_FORMAT_RGBA;
  RgbaImage out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr)) {
    png_image_free(&image);
    return std::nullopt;
  }
  return out;
}

std::optional<RgbaImage> decode_jpeg(std::string_view bytes, size_t max_pixels) {
  const std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitDecompress(), tjDestroy);
  if (!handle) return std::nullopt;
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto size = static_cast<unsigned long>(bytes.size());
  if (tjDecompressHeader3(handle.get(), data, size, &width, &height, &subsampling, &colorspace) ||
      width <= 0 || height <= 0 || static_cast<uint64_t>(width) * height > max_pixels)
    return std::nullopt;
  // Each scan is decoded over the whole image: thousands of them take minutes.
  if (const size_t scans = jpeg_scan_count(bytes); scans > kMaxJpegScans)
    throw InputError("jpeg_scans", "a JPEG image has over " + std::to_string(kMaxJpegScans) +
                                       " scans (progressive passes); decoding them would take "
                                       "too long, so it is refused");
  RgbaImage out;
  out.width = width;
  out.height = height;
  out.rgba.resize(static_cast<size_t>(width) * height * 4);
  if (tjDecompress2(handle.get(), data, size, out.rgba.data(), width, 0, height, TJPF_RGBA, 0))
    return std::nullopt;
  return out;
}

}  // namespace

std::string image_type(std::string_view bytes) {
  if (bytes.substr(0, 8) == "\x89PNG\r\n\x1a\n") return "image/png";
  if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xff\xd8\xff") return "image/jpeg";
  if (bytes.size() >= 12 && bytes.substr(0, 4) == "RIFF" && bytes.substr(8, 4) == "WEBP")
    return "image/webp";
  if (bytes.size() >= 12 && bytes.substr(0, 12) == "\xabKTX 20\xbb\r\n\x1a\n") return "image/ktx2";
  return "";
}

size_t image_pixels(std::string_view bytes) {
  const std::string type = image_type(bytes);
  if (type == "image/png") {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) return 0;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    png_image_free(&image);
    return pixels;
  }
  if (type == "image/jpeg") {
    const std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitDecompress(), tjDestroy);
    int width = 0, height = 0, subsampling = 0, colorspace = 0;
    if (!handle ||
        tjDecompressHeader3(handle.get(), reinterpret_cast<const unsigned char*>(bytes.data()),
                            static_cast<unsigned long>(bytes.size()), &width, &height, &subsampling,
                            &colorspace) ||
        width <= 0 || height <= 0)
      return 0;
    return static_cast<size_t>(width) * static_cast<size_t>(height);
  }
  return 0;
}

std::optional<RgbaImage> decode_image(std::string_view bytes, size_t max_pixels) {
  const std::string type = image_type(bytes);
  if (type == "image/png") return decode_png(bytes, max_pixels);
  if (type == "image/jpeg") return decode_jpeg(bytes, max_pixels);
  return std::nullopt;
}

}  // namespace spheremap
