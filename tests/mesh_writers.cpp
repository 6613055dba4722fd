#include "tests/mesh_writers.h"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace spheremap::testing {
namespace {

template <typename T>
void put(std::string& out, T value, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big))
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

// One value as PLY type `type` (binary) or as text (ASCII, followed by a space).
void put_value(std::string& out, const std::string& type, double value,
               PlyLayout::Encoding encoding) {
  if (encoding == PlyLayout::Encoding::kAscii) {
    char buf[64];
    const bool integer = type != "float" && type != "double";
    const int n = integer ? std::snprintf(buf, sizeof buf, "%lld ", static_cast<long long>(value))
                          : std::snprintf(buf, sizeof buf, "%.17g ", value);
    out.append(buf, static_cast<size_t>(n));
    return;
  }
  const bool big = encoding == PlyLayout::Encoding::kBigEndian;
  if (type == "char") put<int8_t>(out, static_cast<int8_t>(value), big);
  if (type == "uchar") put<uint8_t>(out, static_cast<uint8_t>(value), big);
  if (type == "short") put<int16_t>(out, static_cast<int16_t>(value), big);
  if (type == "ushort") put<uint16_t>(out, static_cast<uint16_t>(value), big);
  if (type == "int") put<int32_t>(out, static_cast<int32_t>(value), big);
  if (type == "uint") put<uint32_t>(out, static_cast<uint32_t>(value), big);
  if (type == "float") put<float>(out, static_cast<float>(value), big);
  if (type == "double") put<double>(out, value, big);
}

void end_line(std::string& out, PlyLayout::Encoding encoding) {
  if (encoding != PlyLayout::Encoding::kAscii) return;
  if (!out.empty() && out.back() == ' ') out.back() = '\n';
}

}  // namespace

std::string binary_stl(const PolygonMesh& mesh, std::string_view header) {
  const FanTriangulation fan = fan_triangulate(mesh);
  std::string out(80, ' ');
  out.replace(0, std::min<size_t>(80, header.size()), header.substr(0, 80));
  put<uint32_t>(out, static_cast<uint32_t>(fan.triangles.size()), false);
  for (const Triangle& t : fan.triangles) {
    for (int k = 0; k < 3; ++k) put<float>(out, 0.0f, false);
    for (uint32_t v : t) {
      put<float>(out, static_cast<float>(mesh.positions[v].x), false);
      put<float>(out, static_cast<float>(mesh.positions[v].y), false);
      put<float>(out, static_cast<float>(mesh.positions[v].z), false);
    }
    put<uint16_t>(out, 0, false);
  }
  return out;
}

std::string ascii_stl(const PolygonMesh& mesh, std::string_view name) {
  std::string out = "solid " + std::string(name) + "\n";
  char buf[128];
  for (const Triangle& t : fan_triangulate(mesh).triangles) {
    out += "  facet normal 0 0 0\n    outer loop\n";
    for (uint32_t v : t) {
      const Vec3& p = mesh.positions[v];
      const int n = std::snprintf(buf, sizeof buf, "      vertex %.9g %.9g %.9g\n", p.x, p.y, p.z);
      out.append(buf, static_cast<size_t>(n));
    }
    out += "    endloop\n  endfacet\n";
  }
  return out + "endsolid " + std::string(name) + "\n";
}

std::string ply(const PolygonMesh& mesh, const PlyLayout& layout) {
  const auto encoding = layout.encoding;
  const char* format = encoding == PlyLayout::Encoding::kAscii          ? "ascii"
                       : encoding == PlyLayout::Encoding::kLittleEndian ? "binary_little_endian"
                                                                        : "binary_big_endian";
  std::string out = std::string("ply\nformat ") + format + " 1.0\ncomment spheremap test\n";
  out += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
  const std::string& pt = layout.position_type;
  if (layout.extras) out += "property float nx\nproperty float ny\nproperty float nz\n";
  out += "property " + pt + " x\nproperty " + pt + " y\nproperty " + pt + " z\n";
  if (layout.extras) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (layout.extras) out += "element edge 1\nproperty int vertex1\nproperty int vertex2\n";
  out += "element face " + std::to_string(mesh.face_count()) + "\n";
  if (layout.extras) out += "property list uchar float texcoord\n";
  out += "property list " + layout.count_type + " " + layout.index_type + " " + layout.list_name +
         "\n";
  if (layout.extras) out += "property int flags\n";
  out += "end_header\n";
  for (const Vec3& p : mesh.positions) {
    if (layout.extras)
      for (int k = 0; k < 3; ++k) put_value(out, "float", 0.5, encoding);
    put_value(out, pt, p.x, encoding);
    put_value(out, pt, p.y, encoding);
    put_value(out, pt, p.z, encoding);
    if (layout.extras)
      for (int k = 0; k < 3; ++k) put_value(out, "uchar", 200, encoding);
    end_line(out, encoding);
  }
  if (layout.extras) {
    put_value(out, "int", 0, encoding);
    put_value(out, "int", 1, encoding);
    end_line(out, encoding);
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (layout.extras) {
      put_value(out, "uchar", 2, encoding);
      put_value(out, "float", 0.25, encoding);
      put_value(out, "float", 0.75, encoding);
    }
    put_value(out, layout.count_type, static_cast<double>(mesh.face_size(f)), encoding);
    for (uint32_t v : mesh.face(f)) put_value(out, layout.index_type, v, encoding);
    if (layout.extras) put_value(out, "int", 7, encoding);
    end_line(out, encoding);
  }
  return out;
}

}  // namespace spheremap::testing
