#include "core/io/jpeg_scans.h"

#include <cstdint>

namespace spheremap {

size_t jpeg_scan_count(std::string_view jpeg, size_t stop_after) {
  auto byte = [&](size_t i) { return static_cast<uint8_t>(jpeg[i]); };
  size_t scans = 0;
  size_t i = 2;  // past SOI
  // Segments are skipped by their length; entropy-coded data (after an SOS header) is
  // walked byte by byte, where 0xFF 0x00 is a stuffed byte and 0xFF 0xD0..D7 a restart.
  while (i + 1 < jpeg.size()) {
    if (byte(i) != 0xFF) {
      ++i;
      continue;
    }
    const uint8_t marker = byte(i + 1);
    if (marker == 0xFF) {  // fill byte before a marker
      ++i;
      continue;
    }
    if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {
      i += 2;  // no length: a stuffed byte, TEM, RSTn or SOI
      continue;
    }
    if (marker == 0xD9) break;  // EOI
    if (i + 3 >= jpeg.size()) break;
    const size_t length = static_cast<size_t>(byte(i + 2)) << 8 | byte(i + 3);
    if (length < 2) break;  // corrupt: libjpeg refuses it too
    if (marker == 0xDA && ++scans > stop_after) break;
    i += 2 + length;
  }
  return scans;
}

}  // namespace spheremap
