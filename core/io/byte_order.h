// Loading little- and big-endian numbers from unaligned bytes (binary STL and PLY, GLB),
// whatever the host's byte order.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <utility>

namespace spheremap {

// T is an arithmetic type of 1, 2, 4 or 8 bytes; `p` needs sizeof(T) readable bytes.
template <typename T>
T load_bytes(const unsigned char* p, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big))
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

template <typename T>
T load_little_endian(const unsigned char* p) {
  return load_bytes<T>(p, false);
}

}  // namespace spheremap
