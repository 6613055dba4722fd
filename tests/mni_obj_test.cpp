// MNI .obj surfaces (core/io/mni_obj.h): read through the .obj extension and by content,
// counts checked before allocation, and each malformed field named.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/io/mesh_format.h"
#include "core/io/mni_obj.h"
#include "core/mesh/input_error.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// `mesh` as an MNI `P` object with colour flag `flag` (0: one colour, 1: per polygon,
// 2: per point), its numbers spread over lines as MNI's tools write them.
std::string mni_text(const PolygonMesh& mesh, int flag = 0) {
  std::string out = "P 0.3 0.3 0.4 10 1 ";
  auto number = [&](size_t n, size_t at) {  // eight a line
    out.append(1, ' ').append(std::to_string(n)).append(at % 8 == 7 ? "\n" : "");
  };
  out.append(std::to_string(mesh.vertex_count())).append("\n");
  char buf[64];
  for (const Vec3& p : mesh.positions) {
    std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g\n", p.x, p.y, p.z);
    out += buf;
  }
  out += "\n";
  for (size_t v = 0; v < mesh.vertex_count(); ++v) out += " 0 0 1\n";
  out.append("\n ").append(std::to_string(mesh.face_count()));
  out.append("\n ").append(std::to_string(flag));
  const size_t colours = flag == 0 ? 1 : flag == 1 ? mesh.face_count() : mesh.vertex_count();
  for (size_t c = 0; c < colours; ++c) out += " 1 1 1 1";
  out += "\n\n";
  for (size_t f = 0; f < mesh.face_count(); ++f) number(mesh.offsets[f + 1], f);
  out += "\n\n";
  for (size_t i = 0; i < mesh.indices.size(); ++i) number(mesh.indices[i], i);
  return out + "\n";
}

std::string parse_error(const std::string& text, const char* check = "parse",
                        const MeshLimits& limits = {}) {
  try {
    parse_mesh_text(text, MeshFormat::kObj, limits);
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), check) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

void expect_same_mesh(const PolygonMesh& read, const PolygonMesh& written) {
  ASSERT_EQ(read.vertex_count(), written.vertex_count());
  for (size_t v = 0; v < written.vertex_count(); ++v) {
    EXPECT_NEAR(read.positions[v].x, written.positions[v].x, 1e-8);
    EXPECT_NEAR(read.positions[v].y, written.positions[v].y, 1e-8);
    EXPECT_NEAR(read.positions[v].z, written.positions[v].z, 1e-8);
  }
  EXPECT_EQ(read.offsets, written.offsets);
  EXPECT_EQ(read.indices, written.indices);
}

TEST(MniObj, ReadsASurfaceThroughTheObjExtensionWithEveryColourFlag) {
  const PolygonMesh sphere = testing::icosphere(2);
  for (int flag : {0, 1, 2}) {
    const std::string text = mni_text(sphere, flag);
    EXPECT_EQ(sniff_mesh_format(text), MeshFormat::kObj);
    expect_same_mesh(parse_mesh_text(text, MeshFormat::kObj, {}), sphere);
  }
  // Polygons other than triangles too: the quads of a cube.
  const PolygonMesh cube = testing::quad_cube(2);
  expect_same_mesh(parse_mni_obj(mni_text(cube)), cube);
}

TEST(MniObj, NamesTheFieldThatIsWrong) {
  const PolygonMesh sphere = testing::icosphere(1);
  const std::string good = mni_text(sphere);
  // Cut inside the points: refused before anything is allocated for them.
  const std::string cut = good.substr(0, good.find('\n', good.find('\n') + 1) + 1);
  EXPECT_NE(parse_error(cut).find("MNI obj line 1: the number of points (42) is more than"),
            std::string::npos)
      << parse_error(cut);
  std::string huge = good;
  huge.replace(huge.find(" 42\n"), 4, " 4000000000\n");
  EXPECT_NE(parse_error(huge).find("the number of points (4000000000) is more than"),
            std::string::npos);
  std::string bad_number = good;
  bad_number.replace(bad_number.find('\n') + 1, 1, " x ");
  EXPECT_NE(
      parse_error(bad_number).find("MNI obj line 2: expected a number for point 0, found \"x\""),
      std::string::npos)
      << parse_error(bad_number);
  // Index 42 of a 42-point surface, at the very end.
  std::string past = good;
  past.replace(past.rfind(' '), std::string::npos, " 42\n");
  EXPECT_NE(parse_error(past).find("names point 42, but the file has 42 points"), std::string::npos)
      << parse_error(past);
  std::string flag = good;
  flag.replace(flag.find("\n 0 1 1 1 1"), 3, "\n 7");
  EXPECT_NE(parse_error(flag).find("the colour flag is 7"), std::string::npos);
  // The second polygon ends where the first does.
  std::string ends = good;
  ends.replace(ends.find(" 3 6 "), 5, " 3 3 ");
  EXPECT_NE(parse_error(ends).find("polygon 1 ends at index 3, less than 3 after"),
            std::string::npos)
      << parse_error(ends);
  EXPECT_NE(parse_error("L 0.5 3\n0 0 0\n1 0 0\n0 1 0\n", "empty").find("a 'L' object"),
            std::string::npos);
  EXPECT_NE(parse_error(good, "too_large", {10, SIZE_MAX}).find("42 points, over the limit of 10"),
            std::string::npos);
}

// A Wavefront file is never taken for MNI, nor an MNI letter followed by more letters.
TEST(MniObj, KnowsWavefrontFromMni) {
  EXPECT_FALSE(looks_like_mni_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_FALSE(looks_like_mni_obj("Pear 1 2 3"));
  EXPECT_TRUE(looks_like_mni_obj("\n  P 0.3 0.3 0.4 10 1 3"));
  EXPECT_EQ(
      parse_mesh_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::kObj, {}).face_count(),
      1u);
}

}  // namespace
}  // namespace spheremap
