#include "core/io/off_binary.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/io/byte_order.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

[[noreturn]] void fail(const std::string& message) {
  throw InputError("parse", "binary OFF: " + message);
}

// The bytes after the header line, read as 32-bit words in one byte order.
class Words {
 public:
  Words(std::string_view data, bool big) : data_(data), big_(big) {}
  size_t left() const { return (data_.size() - pos_) / 4; }
  bool at_end() const { return pos_ == data_.size(); }
  // Nothing when the data ends: the caller says what was cut short.
  std::optional<uint32_t> word() {
    if (data_.size() - pos_ < 4) return std::nullopt;
    const auto* p = reinterpret_cast<const unsigned char*>(data_.data()) + pos_;
    pos_ += 4;
    return load_bytes<uint32_t>(p, big_);
  }
  float number() {
    const auto* p = reinterpret_cast<const unsigned char*>(data_.data()) + pos_;
    pos_ += 4;  // the caller checked left()
    return load_bytes<float>(p, big_);
  }

 private:
  std::string_view data_;
  size_t pos_ = 0;
  bool big_;
};

// The counts fit when every vertex (12 bytes) and every face (at least 16) can be present.
bool counts_fit(std::string_view data, bool big) {
  Words w(data, big);
  const std::optional<uint32_t> v = w.word(), f = w.word(), e = w.word();
  if (!v || !f || !e) return false;
  const uint64_t need = uint64_t{*v} * 12 + uint64_t{*f} * 16;
  return need <= uint64_t{w.left()} * 4;
}

// One reading of the faces: an error message, or the mesh when the file ends with them.
std::optional<PolygonMesh> read(std::string_view data, bool big, bool colours, std::string& error) {
  Words w(data, big);
  const uint32_t vertex_count = *w.word(), face_count = *w.word();
  w.word();  // the edge count, unused
  PolygonMesh mesh;
  mesh.positions.reserve(vertex_count);  // bounded by counts_fit
  for (uint32_t i = 0; i < vertex_count; ++i) {
    Vec3 p;
    p.x = w.number();
    p.y = w.number();
    p.z = w.number();
    mesh.positions.push_back(p);
  }
  std::vector<uint32_t> corners;
  for (uint32_t f = 0; f < face_count; ++f) {
    const std::optional<uint32_t> n = w.word();
    if (!n) return error = "the file ends before face " + std::to_string(f), std::nullopt;
    if (*n < 3 || *n > vertex_count || *n > w.left())
      return error = "face " + std::to_string(f) + " has " + std::to_string(*n) + " corners",
             std::nullopt;
    corners.resize(*n);
    for (uint32_t& c : corners) {
      c = *w.word();
      if (c >= vertex_count)
        return error = "face index " + std::to_string(c) + " is out of range (" +
                       std::to_string(vertex_count) + " vertices)",
               std::nullopt;
    }
    if (colours) {  // Geomview: a count of colour components (0-4), then the components
      const std::optional<uint32_t> k = w.word();
      if (!k || *k > 4 || *k > w.left())
        return error = "face " + std::to_string(f) + " has no valid colour count", std::nullopt;
      for (uint32_t i = 0; i < *k; ++i) w.word();
    }
    mesh.add_face(corners);
  }
  if (!w.at_end()) return error = "bytes follow the last face", std::nullopt;
  return mesh;
}

}  // namespace

bool is_binary_off(std::string_view bytes) {
  const size_t end = bytes.find('\n');
  if (end == std::string_view::npos) return false;
  std::string_view line = bytes.substr(0, end);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  return line == "OFF BINARY";
}

PolygonMesh parse_off_binary(std::string_view bytes) {
  const std::string_view data = bytes.substr(bytes.find('\n') + 1);
  std::string first_error;
  for (bool big : {true, false}) {
    if (!counts_fit(data, big)) continue;
    for (bool colours : {false, true}) {
      std::string error;
      if (std::optional<PolygonMesh> mesh = read(data, big, colours, error)) return *mesh;
      if (first_error.empty())
        first_error = error + " (read " + (big ? "big" : "little") + " endian" +
                      (colours ? ", a colour count after each face)" : ")");
    }
  }
  if (!first_error.empty()) fail(first_error);
  fail("the counts after the header do not fit in the " + std::to_string(data.size()) +
       " bytes that follow it, in either byte order");
}

}  // namespace spheremap
