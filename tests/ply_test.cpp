// The PLY reader: every encoding and index type written from generated meshes, with other
// elements and properties to skip, and hostile files (forged counts, truncations, NaN,
// indices out of range, broken headers).
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "core/io/ply.h"
#include "core/mesh/input_error.h"
#include "tests/mesh_generators.h"
#include "tests/mesh_writers.h"

namespace spheremap {
namespace {

using Encoding = testing::PlyLayout::Encoding;

// The text with the word that begins at `at` replaced.
std::string with_word(std::string text, size_t at, const std::string& word) {
  text.replace(at, text.find_first_of(" \n", at) - at, word);
  return text;
}

std::string error_of(std::string_view bytes) {
  try {
    parse_ply(bytes);
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "parse");
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

void expect_same(const PolygonMesh& read, const PolygonMesh& original, bool exact) {
  ASSERT_EQ(read.vertex_count(), original.vertex_count());
  EXPECT_EQ(read.offsets, original.offsets);
  EXPECT_EQ(read.indices, original.indices);
  for (size_t v = 0; v < read.vertex_count(); ++v) {
    const Vec3& a = read.positions[v];
    const Vec3& b = original.positions[v];
    if (exact) {
      ASSERT_EQ(a, b) << "vertex " << v;
    } else {
      ASSERT_FLOAT_EQ(static_cast<float>(a.x), static_cast<float>(b.x)) << "vertex " << v;
      ASSERT_FLOAT_EQ(static_cast<float>(a.y), static_cast<float>(b.y));
      ASSERT_FLOAT_EQ(static_cast<float>(a.z), static_cast<float>(b.z));
    }
  }
}

TEST(PlyReader, ReadsEveryEncodingAndTypeSkippingTheRest) {
  const PolygonMesh cube = testing::quad_cube(3);  // 56 vertices, 54 quads
  for (Encoding encoding : {Encoding::kAscii, Encoding::kLittleEndian, Encoding::kBigEndian})
    for (const char* position : {"float", "double"})
      for (const char* count : {"uchar", "ushort", "uint", "int", "char"})
        for (const char* index : {"int", "uint", "short", "ushort"})
          for (bool extras : {false, true}) {
            testing::PlyLayout layout;
            layout.encoding = encoding;
            layout.position_type = position;
            layout.count_type = count;
            layout.index_type = index;
            layout.extras = extras;
            layout.list_name = extras ? "vertex_index" : "vertex_indices";
            SCOPED_TRACE(std::string(position) + " " + count + " " + index +
                         (extras ? " extras" : "") + " encoding " +
                         std::to_string(static_cast<int>(encoding)));
            expect_same(parse_ply(testing::ply(cube, layout)), cube,
                        std::string(position) == "double");
          }
}

TEST(PlyReader, ReadsCrlfHeadersAndPropertiesInAnyOrder) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\nobj_info made by hand\r\nelement vertex 4\r\n"
      "property float z\r\nproperty float y\r\nproperty float x\r\nelement face 4\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n"
      "0 0 0\r\n0 0 1\r\n0 1 0\r\n1 0 0\r\n3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n";
  const PolygonMesh m = parse_ply(text);
  ASSERT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.positions[1], (Vec3{1, 0, 0}));  // "0 0 1" is z y x
  EXPECT_EQ(m.face_count(), 4u);
}

// Rhinoceros 6 ends header lines in "\r" alone (the Draco test data's Box.ply was refused at
// line 1). The first line says so; the byte after "end_header\r" is data even when it is
// 0x0A (here the first x, 1 + 10 ulp, begins with it in little endian).
TEST(PlyReader, ReadsHeadersWithCarriageReturnLineEnds) {
  PolygonMesh cube = testing::quad_cube(2);
  uint32_t bits = 0x3F80000Au;
  float x;
  std::memcpy(&x, &bits, 4);
  cube.positions[0].x = x;
  for (Encoding encoding : {Encoding::kAscii, Encoding::kLittleEndian, Encoding::kBigEndian}) {
    testing::PlyLayout layout;
    layout.encoding = encoding;
    std::string text = testing::ply(cube, layout);
    const size_t body = text.find("end_header\n") + 11;
    const size_t end = encoding == Encoding::kAscii ? text.size() : body;
    for (size_t i = 0; i < end; ++i)
      if (text[i] == '\n') text[i] = '\r';
    if (encoding == Encoding::kLittleEndian) {
      ASSERT_EQ(text[body], '\n');
    }
    SCOPED_TRACE("encoding " + std::to_string(static_cast<int>(encoding)));
    expect_same(parse_ply(text), cube, false);
  }
  EXPECT_NE(error_of("ply\rformat ascii 2.0\rend_header\r").find("line 2"), std::string::npos);
}

TEST(PlyReader, ForgedCountsAreRefusedBeforeAllocating) {
  const PolygonMesh tet = testing::icosphere(0);
  for (Encoding encoding : {Encoding::kAscii, Encoding::kLittleEndian, Encoding::kBigEndian}) {
    testing::PlyLayout layout;
    layout.encoding = encoding;
    const std::string ply = testing::ply(tet, layout);
    for (const std::string name : {"vertex", "face"}) {
      std::string forged = ply;
      const std::string line = "element " + name + (name == "vertex" ? " 12\n" : " 20\n");
      forged.replace(forged.find(line), line.size(), "element " + name + " 1000000000\n");
      const std::string message = error_of(forged);
      EXPECT_NE(message.find("declares 1000000000 entries"), std::string::npos) << message;
      EXPECT_NE(message.find("bytes follow the header"), std::string::npos) << message;
    }
  }
  // A list length of 10^9 in one face (uint counts): refused by the bytes left.
  testing::PlyLayout layout;
  layout.count_type = "uint";
  std::string ply = testing::ply(tet, layout);
  const size_t first_face = ply.size() - 20 * (4 + 3 * 4);
  const uint32_t huge = 1'000'000'000;
  std::memcpy(ply.data() + first_face, &huge, 4);
  EXPECT_NE(error_of(ply).find("a list of 1000000000 items"), std::string::npos);
  // A header count past 64 bits.
  std::string wide = testing::ply(tet);
  wide.replace(wide.find("vertex 12"), 9, "vertex 99999999999999999999999");
  EXPECT_NE(error_of(wide).find("not a number"), std::string::npos);
}

// The service's caps, on the declared counts before allocating, and on the triangles of
// the polygons read: "too_large", which it answers 413.
TEST(PlyReader, CountsOverTheLimitsAreTooLarge) {
  const PolygonMesh cube = testing::quad_cube(2);  // 26 vertices, 24 quads = 48 triangles
  auto check = [&](size_t max_vertices, size_t max_triangles) -> std::string {
    MeshLimits limits;
    limits.max_vertices = max_vertices;
    limits.max_triangles = max_triangles;
    try {
      parse_ply(testing::ply(cube), limits);
    } catch (const InputError& e) {
      return e.check() + ": " + e.what();
    }
    return "read";
  };
  EXPECT_EQ(check(26, 48), "read");
  EXPECT_NE(check(25, 48).find("too_large: PLY: 26 vertices and 24 faces"), std::string::npos);
  EXPECT_NE(check(26, 23).find("too_large: PLY: 26 vertices and 24 faces"), std::string::npos);
  EXPECT_NE(check(26, 47).find("too_large: PLY: 48 triangles once its polygons are split"),
            std::string::npos);
}

TEST(PlyReader, TruncatedFilesAreErrorsAtEveryCut) {
  const PolygonMesh sphere = testing::icosphere(1);
  for (Encoding encoding : {Encoding::kLittleEndian, Encoding::kBigEndian}) {
    testing::PlyLayout layout;
    layout.encoding = encoding;
    layout.extras = true;
    const std::string ply = testing::ply(sphere, layout);
    for (size_t cut = 0; cut < ply.size(); cut += 3) error_of(ply.substr(0, cut));
  }
  testing::PlyLayout ascii;
  ascii.encoding = Encoding::kAscii;
  const std::string text = testing::ply(sphere, ascii);
  // Before the last face's last index begins, every cut leaves a value missing.
  const size_t last = text.find_last_of(' ');
  for (size_t cut = 0; cut <= last; cut += 3) error_of(text.substr(0, cut));
}

TEST(PlyReader, RejectsIndicesOutOfRangeAndShortFaces) {
  testing::PlyLayout ascii;
  ascii.encoding = Encoding::kAscii;
  const std::string good = testing::ply(testing::icosphere(0), ascii);
  const size_t last_face = good.rfind("\n3 ") + 1;
  std::string message = error_of(with_word(good, last_face + 2, "12"));
  EXPECT_NE(message.find("1 face corner names a vertex out of range (the first: 12; there are "
                         "12 vertices)"),
            std::string::npos)
      << message;
  EXPECT_NE(error_of(with_word(good, last_face + 2, "-1")).find("vertex index -1"),
            std::string::npos);
  message = error_of(with_word(good, last_face, "2"));
  EXPECT_NE(message.find("a face of 2 corners"), std::string::npos) << message;
  EXPECT_NE(message.find("element 'face' 19 of 20"), std::string::npos) << message;
  // 10 header lines, 12 vertex lines, then faces 0 to 19.
  EXPECT_NE(message.find("line 42"), std::string::npos) << message;
}

TEST(PlyReader, NonFiniteCoordinatesAreCounted) {
  testing::PlyLayout ascii;
  ascii.encoding = Encoding::kAscii;
  std::string text = testing::ply(testing::icosphere(0), ascii);
  text = with_word(text, text.find("end_header\n") + 11, "nan");
  EXPECT_NE(error_of(text).find("1 of 12 vertices has a non-finite"), std::string::npos);
  std::string binary = testing::ply(testing::icosphere(0));
  const float inf = std::numeric_limits<float>::infinity();
  const size_t data = binary.find("end_header\n") + 11;
  std::memcpy(binary.data() + data + 12 * 2 + 4, &inf, 4);  // vertex 2, y
  std::memcpy(binary.data() + data + 12 * 5, &inf, 4);      // vertex 5, x
  EXPECT_NE(error_of(binary).find("2 of 12 vertices"), std::string::npos);
}

TEST(PlyReader, HeaderErrorsNameTheLine) {
  const std::string head = "ply\nformat ascii 1.0\n";
  EXPECT_NE(error_of("PLY\n").find("does not begin with the line 'ply'"), std::string::npos);
  EXPECT_NE(error_of(head + "element vertex 0\n").find("no 'end_header'"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 2.0\nend_header\n").find("line 2"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat binary_middle_endian 1.0\nend_header\n").find("unknown format"),
            std::string::npos);
  EXPECT_NE(error_of(head + "property float x\nend_header\n").find("before any element"),
            std::string::npos);
  EXPECT_NE(error_of(head + "element vertex 1\nproperty quad x\nend_header\n")
                .find("line 4: unknown property type 'quad'"),
            std::string::npos);
  EXPECT_NE(error_of(head + "element vertex 1\nproperty float x\nproperty float y\n"
                            "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0\n")
                .find("lacks x, y or z"),
            std::string::npos);
  EXPECT_NE(error_of(head + "element vertex 0\nproperty float x\nproperty float y\nproperty "
                            "float z\nelement face 0\nproperty list uchar float vertex_indices\n"
                            "end_header\n")
                .find("holds non-integers"),
            std::string::npos);
  EXPECT_NE(error_of(head + "element vertex 5\nend_header\n").find("no properties"),
            std::string::npos);
  // After the first element a line that is no keyword is an error; before it, a free text
  // line (Blender 2.4 wrote one without "comment") is read as a comment.
  EXPECT_NE(error_of(head + "element vertex 0\nproperty float x\nfrobnicate\nend_header\n")
                .find("unknown header keyword"),
            std::string::npos);
  EXPECT_EQ(parse_ply("ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org\n"
                      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
                .face_count(),
            1u);
  EXPECT_NE(error_of(head + "end_header\n").find("no 'vertex' element"), std::string::npos);
}

// Stanford's scans store triangle strips ('tristrips', -1 between strips) instead of faces:
// every other triangle of a strip is reversed so all face the same way, and the
// degenerate ones that join strips are left out. Two strips make a closed tetrahedron.
TEST(PlyReader, ReadsTriangleStrips) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
      "1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n";
  const PolygonMesh mesh = parse_ply(head + "11 0 1 2 3 -1 2 3 0 1 1 1\n");
  const std::vector<uint32_t> expected = {0, 1, 2, 2, 1, 3, 2, 3, 0, 0, 3, 1};
  EXPECT_EQ(mesh.indices, expected);
  EXPECT_EQ(mesh.face_count(), 4u);
  // Binary, little endian: the same strips.
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement tristrips 1\n"
      "property list int int vertex_indices\nend_header\n";
  const float xyz[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  const int32_t strips[12] = {11, 0, 1, 2, 3, -1, 2, 3, 0, 1, 1, 1};
  binary.append(reinterpret_cast<const char*>(strips), sizeof strips);
  EXPECT_EQ(parse_ply(binary).indices, expected);
  // A strip index out of range is named like a face's.
  EXPECT_NE(error_of(head + "4 0 1 2 9\n").find("out of range"), std::string::npos);
}

}  // namespace
}  // namespace spheremap
