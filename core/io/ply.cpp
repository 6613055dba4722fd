#include "core/io/ply.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include "core/io/byte_order.h"
#include "core/io/ply_header.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

using ply::Element;
using ply::Encoding;
using ply::Header;
using ply::Property;
using ply::Type;

[[noreturn]] void fail(const std::string& message) {
  throw InputError("parse", "PLY: " + message);
}

// What a property of the element being read becomes.
// kStrip: a triangle strip list (Stanford's 'tristrips' element), -1 restarting it.
enum class Role : uint8_t { kSkip, kX, kY, kZ, kCorners, kStrip };

// Where an element's values come from: binary bytes or ASCII words. Both fail with
// where they were (element, entry, property) when the file ends early or a value is bad.
class ValueSource {
 public:
  ValueSource(std::string_view bytes, const Header& header)
      : bytes_(bytes),
        pos_(header.data_offset),
        line_(header.lines + 1),
        encoding_(header.encoding) {}

  void at(const Element& element, uint64_t entry, const Property& property) {
    element_ = &element, entry_ = entry, property_ = &property;
  }

  double number(Type type) {
    if (encoding_ == Encoding::kAscii) return ascii_number(type);
    return binary_number(type, take(ply::type_size(type)));
  }

  // A list's length: also refused when even its smallest items could not fit in the rest.
  uint64_t list_length(Type count_type, Type item_type) {
    const double n = number(count_type);
    if (n < 0) fail_here("a list of negative length " + std::to_string(static_cast<long long>(n)));
    const uint64_t length = static_cast<uint64_t>(n);
    const uint64_t each = encoding_ == Encoding::kAscii ? 2 : ply::type_size(item_type);
    if (length > (bytes_.size() - pos_ + 1) / each)
      fail_here("a list of " + std::to_string(length) + " items, more than the remaining " +
                std::to_string(bytes_.size() - pos_) + " bytes hold");
    return length;
  }

  void skip(Type type) {
    if (encoding_ == Encoding::kAscii)
      word();
    else
      take(ply::type_size(type));
  }

  [[noreturn]] void fail_here(const std::string& message) const {
    std::string where = "element '" + element_->name + "' " + std::to_string(entry_) + " of " +
                        std::to_string(element_->count) + ", property '" + property_->name + "'";
    if (encoding_ == Encoding::kAscii) where = "line " + std::to_string(line_) + ", " + where;
    fail(where + ": " + message);
  }

 private:
  const unsigned char* take(size_t size) {
    if (size > bytes_.size() - pos_) fail_here("the file ends (truncated)");
    const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_;
    pos_ += size;
    return p;
  }

  double binary_number(Type type, const unsigned char* p) const {
    const bool big = encoding_ == Encoding::kBinaryBigEndian;
    switch (type) {
      case Type::kInt8:
        return static_cast<int8_t>(p[0]);
      case Type::kUint8:
        return p[0];
      case Type::kInt16:
        return load_bytes<int16_t>(p, big);
      case Type::kUint16:
        return load_bytes<uint16_t>(p, big);
      case Type::kInt32:
        return load_bytes<int32_t>(p, big);
      case Type::kUint32:
        return load_bytes<uint32_t>(p, big);
      case Type::kFloat32:
        return load_bytes<float>(p, big);
      case Type::kFloat64:
        return load_bytes<double>(p, big);
    }
    return 0;
  }

  std::string_view word() {
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == '\n') ++line_;
      if (c != ' ' && c != '\t' && c != '\r' && c != '\n') break;
      ++pos_;
    }
    const size_t start = pos_;
    while (pos_ < bytes_.size() && bytes_[pos_] != ' ' && bytes_[pos_] != '\t' &&
           bytes_[pos_] != '\r' && bytes_[pos_] != '\n')
      ++pos_;
    if (pos_ == start) fail_here("the file ends (truncated)");
    return bytes_.substr(start, pos_ - start);
  }

  double ascii_number(Type type) {
    std::string_view w = word();
    if (!w.empty() && w[0] == '+') w.remove_prefix(1);
    double value = 0;
    std::from_chars_result r{};
    if (ply::is_integer(type)) {
      long long integer = 0;
      r = std::from_chars(w.data(), w.data() + w.size(), integer);
      value = static_cast<double>(integer);
    } else {
      r = std::from_chars(w.data(), w.data() + w.size(), value);
    }
    if (r.ec != std::errc() || r.ptr != w.data() + w.size())
      fail_here("expected a number, found '" + std::string(w.substr(0, 40)) + "'");
    return value;
  }

  std::string_view bytes_;
  size_t pos_;
  size_t line_;
  Encoding encoding_;
  const Element* element_ = nullptr;
  uint64_t entry_ = 0;
  const Property* property_ = nullptr;
};

std::vector<Role> roles_of(const Element& element, bool& has_xyz, bool& has_corners) {
  std::vector<Role> roles;
  unsigned xyz = 0;  // bit 0: x, 1: y, 2: z
  for (const Property& p : element.properties) {
    Role role = Role::kSkip;
    if (element.name == "vertex" && !p.is_list) {
      const unsigned seen = xyz;
      if (p.name == "x") role = Role::kX, xyz |= 1;
      if (p.name == "y") role = Role::kY, xyz |= 2;
      if (p.name == "z") role = Role::kZ, xyz |= 4;
      if (xyz == seen) role = Role::kSkip;  // not x, y, z, or one seen already
    }
    if ((element.name == "face" || element.name == "tristrips") && p.is_list && !has_corners &&
        (p.name == "vertex_indices" || p.name == "vertex_index")) {
      if (!ply::is_integer(p.type))
        fail("the " + element.name + " list '" + p.name + "' holds non-integers");
      role = element.name == "face" ? Role::kCorners : Role::kStrip;
      has_corners = true;
    }
    roles.push_back(role);
  }
  if (element.name == "vertex") has_xyz = xyz == 7;
  return roles;
}

// Triangles of a strip list: each index after the first two makes a triangle with the two
// before it, every other one reversed so all face the same way; -1 starts a new strip,
// and the degenerate triangles that join strips (a vertex twice) are left out.
void read_strips(ValueSource& in, const Property& property, uint64_t length, PolygonMesh& mesh) {
  int64_t a = -1, b = -1;
  bool odd = false;
  for (uint64_t j = 0; j < length; ++j) {
    const double index = in.number(property.type);
    if (index == -1) {
      a = b = -1, odd = false;
      continue;
    }
    if (index < 0 || index > std::numeric_limits<uint32_t>::max())
      in.fail_here("vertex index " + std::to_string(static_cast<long long>(index)));
    const auto c = static_cast<int64_t>(index);
    if (a >= 0 && a != b && b != c && a != c) {
      const uint32_t x = static_cast<uint32_t>(odd ? b : a), y = static_cast<uint32_t>(odd ? a : b);
      for (uint32_t v : {x, y, static_cast<uint32_t>(c)}) mesh.indices.push_back(v);
      if (mesh.indices.size() > std::numeric_limits<uint32_t>::max())
        in.fail_here("more corners than 32-bit offsets can hold");
      mesh.offsets.push_back(static_cast<uint32_t>(mesh.indices.size()));
    }
    if (a >= 0) odd = !odd;
    a = b, b = c;
  }
}

// Appends the element's positions (when `vertices`) and faces (a kCorners role) to mesh.
void read_element(ValueSource& in, const Element& element, const std::vector<Role>& roles,
                  bool vertices, PolygonMesh& mesh) {
  for (uint64_t i = 0; i < element.count; ++i) {
    Vec3 p;
    for (size_t k = 0; k < element.properties.size(); ++k) {
      const Property& property = element.properties[k];
      in.at(element, i, property);
      if (!property.is_list) {
        switch (roles[k]) {
          case Role::kX:
            p.x = in.number(property.type);
            break;
          case Role::kY:
            p.y = in.number(property.type);
            break;
          case Role::kZ:
            p.z = in.number(property.type);
            break;
          default:
            in.skip(property.type);
        }
        continue;
      }
      const uint64_t length = in.list_length(property.count_type, property.type);
      if (roles[k] == Role::kStrip) {
        read_strips(in, property, length, mesh);
        continue;
      }
      if (roles[k] != Role::kCorners) {
        for (uint64_t j = 0; j < length; ++j) in.skip(property.type);
        continue;
      }
      if (length < 3) in.fail_here("a face of " + std::to_string(length) + " corners (3 or more)");
      for (uint64_t j = 0; j < length; ++j) {
        const double index = in.number(property.type);
        if (index < 0 || index > std::numeric_limits<uint32_t>::max())
          in.fail_here("vertex index " + std::to_string(static_cast<long long>(index)));
        mesh.indices.push_back(static_cast<uint32_t>(index));
      }
      if (mesh.indices.size() > std::numeric_limits<uint32_t>::max())
        in.fail_here("more corners than 32-bit offsets can hold");
      mesh.offsets.push_back(static_cast<uint32_t>(mesh.indices.size()));
    }
    if (vertices) mesh.positions.push_back(p);
  }
}

void check_indices_and_positions(const PolygonMesh& mesh) {
  size_t out_of_range = 0;
  uint32_t first = 0;
  for (uint32_t index : mesh.indices)
    if (index >= mesh.positions.size() && out_of_range++ == 0) first = index;
  if (out_of_range > 0)
    fail(counted(out_of_range, "face corner") +
         (out_of_range == 1 ? " names a vertex" : " name vertices") + " out of range (the first: " +
         std::to_string(first) + "; there " + (mesh.positions.size() == 1 ? "is " : "are ") +
         counted(mesh.positions.size(), "vertex", "vertices") + ")");
  size_t non_finite = 0;
  for (const Vec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++non_finite;
  if (non_finite > 0)
    fail(std::to_string(non_finite) + " of " +
         counted(mesh.positions.size(), "vertex", "vertices") +
         (non_finite == 1 ? " has" : " have") + " a non-finite coordinate (NaN or infinity)");
}

}  // namespace

PolygonMesh parse_ply(std::string_view bytes, const MeshLimits& limits) {
  const Header header = ply::parse_header(bytes);
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const Element& e : header.elements) {
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" && !face) face = &e;
  }
  // Without faces, triangle strips (Stanford's scans, e.g. igea.ply, store 'tristrips').
  for (const Element& e : header.elements)
    if (e.name == "tristrips" && !face) face = &e;
  if (!vertex) fail("no 'vertex' element");
  if (!face)  // nothing to map: the check of every reader's point cloud, not a parse error
    throw InputError("empty", "PLY: the file is a point cloud (" + counted(vertex->count, "point") +
                                  ", no 'face' or 'tristrips' element): spheremap maps "
                                  "triangle surfaces");

  // A face is at least one triangle.
  if (vertex->count > limits.max_vertices || face->count > limits.max_triangles)
    throw InputError("too_large", "PLY: " + std::to_string(vertex->count) + " vertices and " +
                                      std::to_string(face->count) + " faces, over the limits of " +
                                      std::to_string(limits.max_vertices) + " vertices and " +
                                      std::to_string(limits.max_triangles) + " triangles");
  PolygonMesh mesh;
  // Counts were checked against the bytes by parse_header and the limits: these are bounded.
  mesh.positions.reserve(vertex->count);
  if (face->name == "face") {  // strips: their sizes are known only as they are read
    mesh.offsets.reserve(face->count + 1);
    mesh.indices.reserve(3 * face->count);
  }
  ValueSource in(bytes, header);
  bool has_xyz = false, has_corners = false;
  for (const Element& element : header.elements) {
    const bool first_of_name = &element == vertex || &element == face;
    std::vector<Role> roles;
    if (first_of_name) {
      roles = roles_of(element, has_xyz, has_corners);
      if (&element == vertex && !has_xyz) fail("the 'vertex' element lacks x, y or z");
      if (&element == face && !has_corners)
        fail("the '" + face->name + "' element has no 'vertex_indices' (or 'vertex_index') list");
    } else {
      roles.assign(element.properties.size(), Role::kSkip);
    }
    // Skipped elements are still read through: a truncated file is an error wherever it ends.
    read_element(in, element, roles, &element == vertex, mesh);
  }
  check_indices_and_positions(mesh);
  const size_t triangles = mesh.indices.size() - 2 * mesh.face_count();
  if (triangles > limits.max_triangles)
    throw InputError("too_large", "PLY: " + std::to_string(triangles) +
                                      " triangles once its polygons are split, over the limit of " +
                                      std::to_string(limits.max_triangles));
  return mesh;
}

}  // namespace spheremap
