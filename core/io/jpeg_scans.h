// The scans of a JPEG, counted from its markers without decoding it. libjpeg-turbo
// decodes every scan over the whole image: a small progressive JPEG of thousands of
// scans takes tens of seconds. TurboJPEG 3 caps them (TJPARAM_SCANLIMIT); the 2.x API
// (Debian 12) has no such cap, so decode_image counts first and refuses past it.
#pragma once

#include <cstddef>
#include <string_view>

namespace spheremap {

// The most scans decode_image accepts in a JPEG (TurboJPEG's documentation suggests 500
// for TJPARAM_SCANLIMIT). A progressive JPEG as encoders write it has about 10.
inline constexpr size_t kMaxJpegScans = 500;

// The start-of-scan (SOS) markers in `jpeg`, counting up to `stop_after` + 1 at most (the
// count then only says "over"). Linear in the bytes; reads past nothing on a truncated or
// corrupt file (it counts what it finds).
size_t jpeg_scan_count(std::string_view jpeg, size_t stop_after = kMaxJpegScans);

}  // namespace spheremap
