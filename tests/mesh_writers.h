// STL and PLY bytes of a mesh, written by the tests (the service has no such writers):
// the readers are tested on files of known content, and the fuzzers seeded with them.
#pragma once

#include <string>
#include <string_view>

#include "core/mesh/mesh.h"

namespace spheremap::testing {

// Fan-triangulated, 3 corners per facet, the normal left 0; `header` fills the 80 bytes.
std::string binary_stl(const PolygonMesh& mesh, std::string_view header = "spheremap test");
std::string ascii_stl(const PolygonMesh& mesh, std::string_view name = "test");

struct PlyLayout {
  enum class Encoding { kAscii, kLittleEndian, kBigEndian } encoding = Encoding::kLittleEndian;
  std::string position_type = "float";  // or "double"
  std::string count_type = "uchar";     // of the face lists
  std::string index_type = "int";       // of their items
  std::string list_name = "vertex_indices";
  // Normals before x, y, z, a colour after them, a texture-coordinate list and a flag per
  // face, and an "edge" element before the faces: all to be skipped by the reader.
  bool extras = false;
};
std::string ply(const PolygonMesh& mesh, const PlyLayout& layout = {});

}  // namespace spheremap::testing
