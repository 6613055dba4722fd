#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "core/io/mesh_format.h"
#include "core/io/mesh_limits.h"
#include "core/io/obj.h"
#include "core/io/off.h"
#include "core/io/off_binary.h"
#include "core/mesh/input_error.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(ObjReader, ReadsCornerSyntaxesNegativeIndicesCommentsAndCrlf) {
  const char* text =
      "# a comment\r\n"
      "mtllib x.mtl\r\n"
      "v 0 0 0\r\n"
      "v 1 0 0 # trailing comment\r\n"
      "v 0 1 0\r\n"
      "v 0 0 1\r\n"
      "vt 0 0\r\nvn 0 0 1\r\ng group\r\ns off\r\nusemtl m\r\n"
      "f 1 3 2\r\n"
      "f 1/1 2/1 4/1\r\n"
      "f 2//1 3//1 4//1\r\n"
      "f -4/1/1 -1/1/1 -2/1/1\r\n";
  PolygonMesh m = parse_obj(text);
  ASSERT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.face_count(), 4u);
  EXPECT_EQ(m.face(3)[0], 0u);  // -4 of 4 vertices
  EXPECT_EQ(m.face(3)[1], 3u);
  EXPECT_EQ(m.face(3)[2], 2u);
  EXPECT_EQ(m.positions[1].x, 1.0);
}

// Lines ended by a lone CR (classic Mac OS) read as lines, in OBJ and OFF alike, with the
// line numbers an error names.
TEST(TextReaders, ReadLinesEndedByALoneCarriageReturn) {
  const PolygonMesh obj =
      parse_obj("# mac\rv 0 0 0\rv 1 0 0 # x\rv 0 1 0\rv 0 0 1\rf 1 3 2\rf 1 2 4\r");
  ASSERT_EQ(obj.vertex_count(), 4u);
  ASSERT_EQ(obj.face_count(), 2u);
  EXPECT_EQ(obj.positions[2].y, 1.0);
  EXPECT_EQ(obj.face(1)[2], 3u);
  const PolygonMesh off = parse_off("OFF\r4 2 0\r0 0 0\r1 0 0\r0 1 0\r0 0 1\r3 0 2 1\r3 0 1 3\r");
  ASSERT_EQ(off.face_count(), 2u);
  EXPECT_EQ(off.positions[3].z, 1.0);
  try {
    parse_obj("v 0 0 0\rv 1 0 0\r\nv 0 1 0\rf 1 2 5\r");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  }
}

TEST(ObjReader, KeepsPolygons) {
  PolygonMesh m = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4 5\n");
  ASSERT_EQ(m.face_count(), 1u);
  EXPECT_EQ(m.face_size(0), 5u);
}

TEST(ObjReader, RejectsOutOfRangeIndexWithLineNumber) {
  try {
    parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "parse");
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

TEST(ObjReader, RejectsBadNumbersAndShortFaces) {
  EXPECT_THROW(parse_obj("v 0 zero 0\n"), InputError);
  EXPECT_THROW(parse_obj("v 0 0 0\nv 1 0 0\nf 1 2\n"), InputError);
  EXPECT_THROW(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"), InputError);
}

// A 2D OBJ ("v x y", as libigl and triangle write planar meshes) reads with z = 0; a file
// mixing 2D and 3D vertices is refused, naming both lines (a cut line is not a flat vertex).
TEST(ObjReader, ReadsA2dFileFlatAndRefusesAMix) {
  const PolygonMesh flat = parse_obj("v 0 0\nv 1 0\nv 0 1.5 \r\nf 1 2 3\n");
  ASSERT_EQ(flat.vertex_count(), 3u);
  EXPECT_EQ(flat.positions[2], (Vec3{0, 1.5, 0}));
  EXPECT_EQ(flat.face_count(), 1u);
  try {
    parse_obj("v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "parse");
    const std::string what = e.what();
    EXPECT_NE(what.find("line 3"), std::string::npos) << what;
    EXPECT_NE(what.find("line 1 has 3"), std::string::npos) << what;
  }
  EXPECT_THROW(parse_obj("v 0 1\nv 0 0 0\n"), InputError);
  EXPECT_THROW(parse_obj("v 0\n"), InputError);  // one coordinate is no vertex
}

// The OBJ spec's line continuation: a backslash at the end of a line joins the next.
TEST(ObjReader, JoinsLinesContinuedByABackslash) {
  const PolygonMesh m = parse_obj(
      "v 0 0 \\\r\n  0\n"  // "v 0 0 0" over two CRLF lines
      "v 1 \\\n0 \\\n0\n"  // over three
      "v 0 1 0\nv 0 0 1\n"
      "f 1 2 \\\n 3 4\n"  // a face over two
      "# a comment ending in a backslash continues nothing \\\n"
      "f 1 2 3\n");
  ASSERT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.positions[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(m.positions[1], (Vec3{1, 0, 0}));
  ASSERT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.face_size(0), 4u);
  EXPECT_EQ(m.face(0)[3], 3u);
  // Errors after a continuation name the line they were found on.
  try {
    parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\n9\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 6"), std::string::npos) << e.what();
  }
  // A backslash on the last line of the file: the line ends there.
  EXPECT_EQ(parse_obj("v 0 0 0 \\").vertex_count(), 1u);
}

TEST(ObjWriter, RoundTripsExactly) {
  PolygonMesh m = parse_obj("v 0.1 -2.5e-7 3\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\n");
  PolygonMesh again = parse_obj(format_obj(m));
  EXPECT_EQ(again.positions, m.positions);
  EXPECT_EQ(again.indices, m.indices);
  EXPECT_EQ(again.offsets, m.offsets);
}

TEST(OffReader, ReadsPolygonsAndComments) {
  PolygonMesh m =
      parse_off("OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 2 3\n");
  EXPECT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.face_size(1), 4u);
}

// OFF is whitespace-separated: libigl's tutorial data breaks each face over lines, with
// blank lines between; what follows a record on its line (colours) is skipped.
TEST(OffReader, ReadsRecordsBrokenOverLinesAndSkipsColours) {
  PolygonMesh m = parse_off(
      "OFF\n4 2 0\n0 0 0\n1 0\n0\n0 1 0 255 0 0\n0 0 1\n3\n0 1\n\n2\n4 0 1 2 3 0.5 0.5 0.5\n");
  EXPECT_EQ(m.vertex_count(), 4u);
  ASSERT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.face_size(0), 3u);
  EXPECT_EQ(m.face_size(1), 4u);
  EXPECT_EQ(m.positions[1].x, 1.0);
  EXPECT_EQ(m.positions[2].y, 1.0);
  EXPECT_THROW(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"), InputError);
}

TEST(OffReader, RejectsHugeDeclaredCountsBeforeAllocating) {
  try {
    parse_off("OFF\n2000000000 2000000000 0\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("do not fit"), std::string::npos) << e.what();
  }
}

TEST(OffReader, RejectsTruncatedFilesAndBadIndices) {
  EXPECT_THROW(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n"), InputError);
  EXPECT_THROW(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), InputError);
  EXPECT_THROW(parse_off("PLY\n"), InputError);
  // An index one past the last is said to look like counting from 1 (OFF counts from 0).
  try {
    parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 1 2 3\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("count from 1"), std::string::npos) << e.what();
  }
  try {
    parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("count from 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace spheremap

namespace spheremap {
namespace {

// A binary OFF of `mesh`: Geomview's layout (big endian, a colour count after each face,
// here 1 component) or pmp's (little endian, none).
std::string binary_off(const PolygonMesh& mesh, bool big, bool colours) {
  std::string out = "OFF BINARY\n";
  auto put = [&](auto value) {
    unsigned char b[4];
    std::memcpy(b, &value, 4);
    if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + 4);
    out.append(reinterpret_cast<const char*>(b), 4);
  };
  put(static_cast<uint32_t>(mesh.vertex_count()));
  put(static_cast<uint32_t>(mesh.face_count()));
  put(uint32_t{0});
  for (const Vec3& p : mesh.positions) {
    put(static_cast<float>(p.x));
    put(static_cast<float>(p.y));
    put(static_cast<float>(p.z));
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    put(static_cast<uint32_t>(mesh.face(f).size()));
    for (uint32_t c : mesh.face(f)) put(c);
    if (colours) {
      put(uint32_t{1});
      put(0.5f);
    }
  }
  return out;
}

// pmp's data (beetle.off, fairing-cross.off) is binary OFF, refused as "binary bytes" before.
TEST(OffReader, ReadsBinaryOffInBothByteOrdersWithAndWithoutFaceColours) {
  const PolygonMesh cube = testing::quad_cube(2);
  for (bool big : {false, true})
    for (bool colours : {false, true}) {
      SCOPED_TRACE(std::string(big ? "big" : "little") + (colours ? " colours" : ""));
      const std::string bytes = binary_off(cube, big, colours);
      ASSERT_TRUE(is_binary_off(bytes));
      const PolygonMesh m = parse_mesh_text(bytes, MeshFormat::kOff, MeshLimits{});
      ASSERT_EQ(m.vertex_count(), cube.vertex_count());
      EXPECT_EQ(m.offsets, cube.offsets);
      EXPECT_EQ(m.indices, cube.indices);
      for (size_t v = 0; v < m.vertex_count(); ++v)
        ASSERT_EQ(m.positions[v].x, static_cast<double>(static_cast<float>(cube.positions[v].x)));
    }
}

TEST(OffReader, RefusesBrokenBinaryOffWithAParseError) {
  const std::string good = binary_off(testing::quad_cube(2), false, false);
  auto error_of = [](const std::string& bytes) {
    try {
      parse_off_binary(bytes);
    } catch (const InputError& e) {
      EXPECT_EQ(e.check(), "parse");
      return std::string(e.what());
    }
    ADD_FAILURE() << "expected an InputError";
    return std::string();
  };
  for (size_t cut = 11; cut < good.size(); cut += 7) error_of(good.substr(0, cut));
  EXPECT_NE(error_of(good + "xxxx").find("bytes follow the last face"), std::string::npos);
  std::string forged = good;
  const uint32_t huge = 0x7fffffff;
  std::memcpy(forged.data() + 11, &huge, 4);  // the vertex count
  EXPECT_NE(error_of(forged).find("do not fit"), std::string::npos);
  std::string index = good;
  const uint32_t far = 1000;
  std::memcpy(index.data() + index.size() - 4, &far, 4);  // the last corner
  EXPECT_NE(error_of(index).find("out of range"), std::string::npos);
}

}  // namespace
}  // namespace spheremap
