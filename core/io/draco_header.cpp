#include "core/io/draco_header.h"

#include <string>

#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

constexpr int kMaxMetadataDepth = 16;

[[noreturn]] void refuse(const std::string& why) {
  throw InputError("gltf", "the Draco stream " + why);
}

// A cursor over the stream; every read checks what is left.
class Cursor {
 public:
  explicit Cursor(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  uint8_t byte() {
    if (at_ >= bytes_.size()) refuse("ends inside its header");
    return bytes_[at_++];
  }
  uint64_t varint() {  // LEB128, as Draco writes its counts (at most 32 bits)
    uint64_t value = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      const uint8_t b = byte();
      value |= static_cast<uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return value;
    }
    refuse("has a count of over 32 bits");
  }
  void skip(uint64_t count) {
    if (count > bytes_.size() - at_) refuse("declares metadata past its end");
    at_ += static_cast<size_t>(count);
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
};

void skip_metadata(Cursor& in, int depth) {
  if (depth > kMaxMetadataDepth)
    refuse("nests metadata over " + std::to_string(kMaxMetadataDepth) + " deep");
  for (uint64_t entries = in.varint(); entries > 0; --entries) {
    in.skip(in.byte());    // name
    in.skip(in.varint());  // value
  }
  for (uint64_t subs = in.varint(); subs > 0; --subs) {
    in.skip(in.byte());  // name
    skip_metadata(in, depth + 1);
  }
}

// The header's flags and, when they say so, the metadata: per attribute, then the file's.
void skip_flags_and_metadata(Cursor& in) {
  const uint16_t flags = static_cast<uint16_t>(in.byte() | in.byte() << 8);
  if (!(flags & 0x8000)) return;
  for (uint64_t attributes = in.varint(); attributes > 0; --attributes) {
    in.varint();  // the attribute's id
    skip_metadata(in, 0);
  }
  skip_metadata(in, 0);
}

}  // namespace

uint64_t read_draco_point_count(std::span<const uint8_t> stream) {
  Cursor in(stream);
  for (int i = 0; i < 5; ++i) in.byte();  // DRACO
  in.byte(), in.byte();                   // the version
  if (in.byte() != 0) refuse("is not a point cloud");
  in.byte();  // the method: sequential and kd-tree both begin with the count
  skip_flags_and_metadata(in);
  uint32_t points = 0;  // an int32, little-endian
  for (int shift = 0; shift < 32; shift += 8) points |= static_cast<uint32_t>(in.byte()) << shift;
  return points;
}

DracoCounts read_draco_counts(std::span<const uint8_t> stream) {
  Cursor in(stream);
  const char magic[] = "DRACO";
  for (int i = 0; i < 5; ++i)
    if (in.byte() != static_cast<uint8_t>(magic[i])) refuse("does not start with DRACO");
  const int major = in.byte(), minor = in.byte();
  // Point clouds are bitstream 2.3: said as what they are, not as a wrong version.
  const uint8_t type = in.byte();
  if (type == 0)
    refuse("is a point cloud (" + counted(read_draco_point_count(stream), "point") +
           ", no faces): spheremap maps triangle surfaces");
  if (major != 2 || minor != 2)
    refuse("is bitstream version " + std::to_string(major) + "." + std::to_string(minor) +
           "; glTF's KHR_draco_mesh_compression streams are version 2.2");
  if (type != 1) refuse("has geometry type " + std::to_string(type) + ", not a triangle mesh");
  const uint8_t method = in.byte();
  skip_flags_and_metadata(in);
  DracoCounts counts;
  if (method == 0) {  // sequential
    counts.faces = in.varint();
    counts.vertices = in.varint();
  } else if (method == 1) {  // edgebreaker: traversal type, then the counts
    in.byte();
    counts.vertices = in.varint();
    counts.faces = in.varint();
  } else {
    refuse("uses an unknown encoding method " + std::to_string(method));
  }
  return counts;
}

}  // namespace spheremap
