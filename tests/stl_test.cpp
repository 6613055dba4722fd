// The STL reader: binary and ASCII files written from generated meshes, and hostile ones
// (forged counts, truncations, NaN, a binary header that begins with "solid").
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/io/stl.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"
#include "core/outputs/report_json.h"
#include "tests/mesh_generators.h"
#include "tests/mesh_writers.h"

namespace spheremap {
namespace {

std::string error_of(std::string_view bytes) {
  try {
    parse_stl(bytes);
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "parse");
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

void set_count(std::string& stl, uint32_t count) {
  std::memcpy(stl.data() + 80, &count, 4);
}

// Every facet's 3 corners as vertices of their own; welded, the closed sphere again.
void expect_welds_to(const PolygonMesh& read, const PolygonMesh& original) {
  const size_t triangles = fan_triangulate(original).triangles.size();
  ASSERT_EQ(read.face_count(), triangles);
  EXPECT_EQ(read.vertex_count(), 3 * triangles);
  EXPECT_TRUE(read.is_triangle_mesh());
  const PreparedMesh prepared = prepare_mesh(read, {});
  EXPECT_EQ(prepared.welded.mesh.vertex_count(), original.vertex_count());
  EXPECT_TRUE(input_failures(prepared).empty()) << topology_json(prepared).dump(2);
}

TEST(StlReader, BinaryWeldsToTheClosedMesh) {
  const PolygonMesh sphere = testing::icosphere(2);
  const std::string stl = testing::binary_stl(sphere);
  EXPECT_TRUE(is_binary_stl(stl));
  const PolygonMesh read = parse_stl(stl);
  expect_welds_to(read, sphere);
  EXPECT_FLOAT_EQ(static_cast<float>(read.positions[0].x),
                  static_cast<float>(sphere.positions[fan_triangulate(sphere).triangles[0][0]].x));
}

TEST(StlReader, BinaryWhoseHeaderBeginsWithSolidIsReadAsBinary) {
  const PolygonMesh cube = testing::quad_cube(2);
  const std::string stl = testing::binary_stl(cube, "solid cube exported by a CAD tool");
  EXPECT_TRUE(is_binary_stl(stl));
  expect_welds_to(parse_stl(stl), cube);
}

TEST(StlReader, AsciiWeldsToTheClosedMesh) {
  const PolygonMesh sphere = testing::icosphere(2);
  const std::string stl = testing::ascii_stl(sphere);
  EXPECT_FALSE(is_binary_stl(stl));
  expect_welds_to(parse_stl(stl), sphere);
  // Two solids in one file, CRLF line ends, any indentation: one mesh.
  std::string two = testing::ascii_stl(testing::icosphere(0), "a") +
                    testing::ascii_stl(testing::icosphere(0), "b");
  std::string crlf;
  for (char c : two) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_EQ(parse_stl(crlf).face_count(), 40u);
  // Classic Mac OS line ends, a lone CR (PrusaSlicer's 20mmbox-CR.stl): the same mesh.
  std::string cr = two;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  const PolygonMesh from_cr = parse_stl(cr), from_lf = parse_stl(two);
  ASSERT_EQ(from_cr.face_count(), 40u);
  EXPECT_EQ(from_cr.positions, from_lf.positions);
}

TEST(StlReader, ForgedBinaryCountIsRefusedBeforeAllocating) {
  std::string stl = testing::binary_stl(testing::icosphere(0));
  set_count(stl, 1'000'000'000);
  const std::string message = error_of(stl);
  EXPECT_NE(message.find("1000000000 triangles"), std::string::npos) << message;
  EXPECT_NE(message.find("50000000084 bytes"), std::string::npos) << message;
  EXPECT_NE(message.find("has " + std::to_string(stl.size())), std::string::npos) << message;
  // The same with a header that begins with "solid": read as ASCII, which fails, and the
  // message still gives the binary reading's counts.
  std::string solid = testing::binary_stl(testing::icosphere(0), "solid forged");
  set_count(solid, 1'000'000'000);
  const std::string solid_message = error_of(solid);
  EXPECT_NE(solid_message.find("1000000000 triangles"), std::string::npos) << solid_message;
  // The largest count there is.
  set_count(stl, std::numeric_limits<uint32_t>::max());
  EXPECT_NE(error_of(stl).find("4294967295 triangles"), std::string::npos);
}

// The service's cap on triangles, from the declared count (binary) or while reading
// (ASCII): "too_large", which it answers 413.
TEST(StlReader, TrianglesOverTheLimitAreTooLarge) {
  const PolygonMesh sphere = testing::icosphere(1);  // 80 triangles
  MeshLimits limits;
  limits.max_triangles = 80;
  EXPECT_EQ(parse_stl(testing::binary_stl(sphere), limits).face_count(), 80u);
  EXPECT_EQ(parse_stl(testing::ascii_stl(sphere), limits).face_count(), 80u);
  limits.max_triangles = 79;
  for (const std::string& stl : {testing::binary_stl(sphere), testing::ascii_stl(sphere),
                                 testing::binary_stl(sphere, "solid header")}) {
    try {
      parse_stl(stl, limits);
      ADD_FAILURE() << "expected too_large";
    } catch (const InputError& e) {
      EXPECT_EQ(e.check(), "too_large");
      EXPECT_NE(std::string(e.what()).find("80 triangles, over the limit of 79"), std::string::npos)
          << e.what();
    }
  }
}

TEST(StlReader, TruncatedFilesAreErrorsAtEveryCut) {
  const std::string binary = testing::binary_stl(testing::icosphere(1));
  for (size_t cut = 0; cut < binary.size(); cut += 7) error_of(binary.substr(0, cut));
  error_of(binary.substr(0, binary.size() - 1));
  error_of(binary + "x");
  const std::string ascii = testing::ascii_stl(testing::icosphere(1));
  // Cut anywhere before "endsolid", the file ends inside the solid.
  const size_t last_line = ascii.rfind("endsolid");
  for (size_t cut = 0; cut < last_line; cut += 5) error_of(ascii.substr(0, cut));
}

TEST(StlReader, NonFiniteCoordinatesAreCounted) {
  std::string binary = testing::binary_stl(testing::icosphere(1));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(binary.data() + 84 + 50 * 3 + 12, &nan, 4);      // triangle 3, corner 0, x
  std::memcpy(binary.data() + 84 + 50 * 7 + 24 + 8, &inf, 4);  // triangle 7, corner 1, z
  const std::string message = error_of(binary);
  EXPECT_NE(message.find("2 of 240 corners"), std::string::npos) << message;
  EXPECT_NE(message.find("first in triangle 3"), std::string::npos) << message;
  std::string ascii = testing::ascii_stl(testing::icosphere(0));
  const size_t x = ascii.find("vertex ") + 7;
  ascii.replace(x, ascii.find(' ', x) - x, "nan");
  EXPECT_NE(error_of(ascii).find("1 of 60 corners"), std::string::npos);
}

TEST(StlReader, AsciiErrorsNameTheLine) {
  const std::string ok =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
  EXPECT_EQ(parse_stl(ok).face_count(), 1u);
  std::string four = ok;
  four.insert(four.find("endloop"), "vertex 1 1 0\n");
  EXPECT_NE(error_of(four).find("line 7: a facet with more than 3 vertices"), std::string::npos);
  std::string two = ok;
  two.erase(two.find("vertex 0 1 0\n"), 13);
  EXPECT_NE(error_of(two).find("line 6: a facet needs 3 vertices, found 2"), std::string::npos);
  std::string word = ok;
  word.replace(word.find("vertex 1 0 0"), 12, "vertex 1 zero 0");
  EXPECT_NE(error_of(word).find("line 5"), std::string::npos);
  EXPECT_NE(error_of("solid s\nendfacet\nendsolid\n").find("line 2"), std::string::npos);
  EXPECT_NE(error_of(ok.substr(0, ok.find("endsolid"))).find("before 'endsolid'"),
            std::string::npos);
  EXPECT_NE(error_of("hello").find("too short for binary STL"), std::string::npos);
  EXPECT_NE(error_of(std::string(200, 'x')).find("does not begin with 'solid'"), std::string::npos);
}

// No per-facet allocation: 250,000 triangles (12.5 MB) take milliseconds. The bound is
// loose on purpose (a loaded CI machine); it catches a reader that went quadratic.
TEST(StlReader, ReadsAQuarterMillionTrianglesQuickly) {
  const PolygonMesh sphere = testing::icosphere(6);  // 81,920 triangles
  std::string one = testing::binary_stl(sphere);
  std::string stl = one.substr(0, 84);
  for (int k = 0; k < 3; ++k) stl += one.substr(84);
  set_count(stl, 3 * 81'920);
  const auto start = std::chrono::steady_clock::now();
  const PolygonMesh read = parse_stl(stl);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(read.face_count(), 3u * 81'920);
  EXPECT_LT(seconds, 2.0);
}

}  // namespace
}  // namespace spheremap
