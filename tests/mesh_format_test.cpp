// Telling mesh formats apart: by extension (read_mesh_file) and by their bytes (uploads
// without a telling content type).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/io/glb_writer.h"
#include "core/io/mesh_file.h"
#include "core/io/mesh_format.h"
#include "core/io/obj.h"
#include "core/mesh/input_error.h"
#include "tests/mesh_generators.h"
#include "tests/mesh_writers.h"

namespace spheremap {
namespace {

TEST(MeshFormat, SniffsEveryFormatFromItsBytes) {
  const PolygonMesh sphere = testing::icosphere(1);
  GlbMesh glb;
  glb.positions = sphere.positions;
  glb.triangles = fan_triangulate(sphere).triangles;
  EXPECT_EQ(sniff_mesh_format(format_glb(glb)), MeshFormat::kGlb);
  EXPECT_EQ(sniff_mesh_format(" \n{\"asset\": {\"version\": \"2.0\"}}"), MeshFormat::kGltf);
  EXPECT_EQ(sniff_mesh_format("\xEF\xBB\xBF{\"asset\": {}}"), MeshFormat::kGltf);
  EXPECT_EQ(sniff_mesh_format(format_obj(sphere)), MeshFormat::kObj);
  EXPECT_EQ(sniff_mesh_format("# exported\n\nmtllib a.mtl\nv 0 0 0\n"), MeshFormat::kObj);
  EXPECT_EQ(sniff_mesh_format("# a comment\no thing\n"), MeshFormat::kObj);
  std::string long_header;
  for (int line = 0; line < 500; ++line) long_header += "# exported by a tool, line\n\n";
  EXPECT_EQ(sniff_mesh_format(long_header + format_obj(sphere)), MeshFormat::kObj);
  EXPECT_EQ(sniff_mesh_format("OFF\n4 4 0\n"), MeshFormat::kOff);
  EXPECT_EQ(sniff_mesh_format(testing::ascii_stl(sphere)), MeshFormat::kStl);
  EXPECT_EQ(sniff_mesh_format(testing::binary_stl(sphere)), MeshFormat::kStl);
  EXPECT_EQ(sniff_mesh_format(testing::binary_stl(sphere, "solid header")), MeshFormat::kStl);
  EXPECT_EQ(sniff_mesh_format(testing::ply(sphere)), MeshFormat::kPly);
  EXPECT_EQ(sniff_mesh_format("ply\r\nformat ascii 1.0\r\n"), MeshFormat::kPly);
  EXPECT_EQ(sniff_mesh_format("ply\rformat binary_little_endian 1.0\r"), MeshFormat::kPly);
  EXPECT_EQ(sniff_mesh_format(""), std::nullopt);
  EXPECT_EQ(sniff_mesh_format(std::string(1000, '\0')), std::nullopt);
  EXPECT_EQ(sniff_mesh_format("hello world\n"), std::nullopt);
  EXPECT_EQ(sniff_mesh_format(std::string(100, '#') + "\n"), std::nullopt);
}

TEST(MeshFormat, ExtensionsAreCaseInsensitive) {
  EXPECT_EQ(format_from_extension("STL"), MeshFormat::kStl);
  EXPECT_EQ(format_from_extension("Ply"), MeshFormat::kPly);
  EXPECT_EQ(format_from_extension("obj"), MeshFormat::kObj);
  EXPECT_EQ(format_from_extension("stla"), std::nullopt);
  EXPECT_EQ(lowercase_extension("dir.v2/Mesh.STL"), "stl");
  EXPECT_EQ(lowercase_extension("dir.v2/mesh"), "");
}

class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("spheremap_mesh_format_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            std::to_string(reinterpret_cast<uintptr_t>(this)));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(MeshFiles, ReadsStlAndPlyByExtensionInAnyCase) {
  const PolygonMesh cube = testing::quad_cube(2);
  const PolygonMesh stl = read_mesh_file(write("cube.STL", testing::binary_stl(cube)));
  EXPECT_EQ(stl.face_count(), 2 * cube.face_count());  // quads fanned into triangles
  const PolygonMesh ascii = read_mesh_file(write("cube.stl", testing::ascii_stl(cube)));
  EXPECT_EQ(ascii.face_count(), 2 * cube.face_count());
  const PolygonMesh ply = read_mesh_file(write("cube.Ply", testing::ply(cube)));
  EXPECT_EQ(ply.face_count(), cube.face_count());
  EXPECT_EQ(ply.indices, cube.indices);
}

TEST_F(MeshFiles, UnknownExtensionsListEveryFormat) {
  try {
    read_mesh_file(write("cube.3ds", "x"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "io");
    const std::string message = e.what();
    for (const char* ext : {".obj", ".off", ".stl", ".ply", ".glb", ".gltf"})
      EXPECT_NE(message.find(ext), std::string::npos) << message;
  }
}

// A file that is not the text its extension says: a PNG renamed .obj, an empty file.
TEST(MeshFormat, BinaryOrEmptyTextFilesSayWhatTheyAre) {
  auto message = [](std::string_view bytes, MeshFormat format) {
    try {
      parse_mesh_text(bytes, format);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
  const std::string as_obj = message(png, MeshFormat::kObj);
  EXPECT_NE(as_obj.find("not an OBJ file: it holds binary bytes"), std::string::npos) << as_obj;
  EXPECT_NE(as_obj.find("starts with \"\\x89PNG"), std::string::npos) << as_obj;
  EXPECT_NE(as_obj.find("(a NUL at byte 8, line 3;"), std::string::npos) << as_obj;
  // A text file with one stray NUL (ufbx's zbrush_cut_sphere.obj) is told where it is.
  const std::string stray = std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n") + '\0' + "\n";
  EXPECT_NE(message(stray, MeshFormat::kObj).find("(a NUL at byte 32, line 5;"), std::string::npos)
      << message(stray, MeshFormat::kObj);
  EXPECT_NE(message(png, MeshFormat::kOff).find("not an OFF file"), std::string::npos);
  EXPECT_EQ(message("", MeshFormat::kObj), "empty file (0 bytes)");
  EXPECT_EQ(message("", MeshFormat::kStl), "empty file (0 bytes)");
  // A binary STL renamed .obj is named as what it looks like.
  const std::string stl = testing::binary_stl(testing::icosphere(1));
  EXPECT_NE(message(stl, MeshFormat::kObj).find("it looks like STL"), std::string::npos)
      << message(stl, MeshFormat::kObj);
}

}  // namespace
}  // namespace spheremap
