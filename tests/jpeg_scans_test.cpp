// A JPEG of thousands of scans is refused before it is decoded (core/io/jpeg_scans.h):
// libjpeg-turbo 2.x would decode each over the whole image, for tens of seconds.
#include "core/io/jpeg_scans.h"

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/io/image_reader.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

// A 64 x 64 progressive JPEG (libjpeg-turbo's own scan script: about 10 scans).
std::string progressive_jpeg() {
  std::vector<unsigned char> rgb(64 * 64 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<unsigned char>(i * 7 % 251);
  const std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitCompress(), tjDestroy);
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  EXPECT_EQ(tjCompress2(handle.get(), rgb.data(), 64, 0, 64, TJPF_RGB, &jpeg, &size, TJSAMP_420, 90,
                        TJFLAG_PROGRESSIVE),
            0);
  std::string out(reinterpret_cast<char*>(jpeg), size);
  tjFree(jpeg);
  return out;
}

// `jpeg` with its shortest scan (SOS segment and entropy-coded data) repeated until it
// has `scans` scans: what a small crafted file of many progressive passes looks like.
std::string with_scans(const std::string& jpeg, size_t scans) {
  std::string shortest;
  for (size_t at = jpeg.find("\xff\xda"); at != std::string::npos;) {
    const size_t next = std::min(jpeg.find("\xff\xda", at + 2), jpeg.rfind("\xff\xd9"));
    if (shortest.empty() || next - at < shortest.size()) shortest = jpeg.substr(at, next - at);
    at = jpeg.find("\xff\xda", at + 2);
  }
  std::string out = jpeg.substr(0, jpeg.rfind("\xff\xd9"));
  for (size_t n = jpeg_scan_count(jpeg, SIZE_MAX); n < scans; ++n) out += shortest;
  return out + "\xff\xd9";
}

TEST(JpegScans, AnEncodersProgressiveJpegHasAFewScansAndDecodes) {
  const std::string jpeg = progressive_jpeg();
  const size_t scans = jpeg_scan_count(jpeg, SIZE_MAX);
  EXPECT_GE(scans, 2u);
  EXPECT_LT(scans, 20u);
  const auto image = decode_image(jpeg, 1 << 20);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 64);
}

TEST(JpegScans, StuffedBytesAndRestartsAreNotMarkers) {
  // SOI, an SOS header, entropy data holding FF 00 and FF D3, a second SOS, EOI.
  const std::string jpeg = std::string("\xff\xd8", 2) + std::string("\xff\xda\x00\x02", 4) +
                           std::string("\x12\xff\x00\x34\xff\xd3\x56", 7) +
                           std::string("\xff\xda\x00\x03\x00", 5) + std::string("\xff\xd9", 2);
  EXPECT_EQ(jpeg_scan_count(jpeg, SIZE_MAX), 2u);
  EXPECT_EQ(jpeg_scan_count(jpeg.substr(0, 9), SIZE_MAX), 1u);  // truncated: what it finds
}

// 10,000 scans in a small file: refused in milliseconds with a clear error, rather than
// decoded for tens of seconds. At the limit it still decodes.
TEST(JpegScans, AJpegOfTooManyScansIsRefusedBeforeDecoding) {
  const std::string crafted = with_scans(progressive_jpeg(), 10000);
  EXPECT_EQ(jpeg_scan_count(crafted, SIZE_MAX), 10000u);
  EXPECT_EQ(jpeg_scan_count(crafted), kMaxJpegScans + 1);  // stops counting past the limit
  const auto start = std::chrono::steady_clock::now();
  try {
    decode_image(crafted, 1 << 20);
    ADD_FAILURE() << "decoded a JPEG of 10,000 scans";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "jpeg_scans");
    EXPECT_NE(std::string(e.what()).find("500 scans"), std::string::npos) << e.what();
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Refused before decoding (the check above); the time is printed, not asserted.
  std::printf("%zu-byte JPEG of 10000 scans refused in %.4f s\n", crafted.size(), seconds);
  EXPECT_NO_THROW(decode_image(with_scans(progressive_jpeg(), kMaxJpegScans), 1 << 20));
}

}  // namespace
}  // namespace spheremap
