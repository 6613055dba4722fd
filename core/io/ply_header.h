// The header of a PLY file (Stanford polygon format): its encoding and its elements, each
// with a count and properties (scalars, or lists with a count type and an item type).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace spheremap::ply {

enum class Encoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
enum class Type : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

size_t type_size(Type type);
bool is_integer(Type type);

struct Property {
  std::string name;
  Type type = Type::kFloat32;  // of the scalar, or of a list's items
  bool is_list = false;
  Type count_type = Type::kUint8;  // lists only
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
  // The fewest bytes (binary: every list empty) or characters (ASCII: one digit and a
  // separator per value) one element can take: a declared count is checked against it.
  uint64_t min_bytes(Encoding encoding) const;
};

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  size_t data_offset = 0;  // the first byte after "end_header" and its line end
  size_t lines = 0;        // header lines, for ASCII line numbers
};

// Throws InputError("parse") naming the header line on anything it does not understand,
// and when an element's declared count cannot fit in the bytes after the header.
Header parse_header(std::string_view bytes);

}  // namespace spheremap::ply
