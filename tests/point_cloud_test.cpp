// Point clouds (vertices, no faces) in each format are refused saying that they are point
// clouds, files of lines saying lines; every format under the one check `empty` (the API's
// 422 not_mappable).
#include <gtest/gtest.h>

#include "core/io/mesh_format.h"
#include "core/io/obj.h"
#include "core/io/ply.h"
#include "core/outputs/report_json.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/gltf_files.h"

namespace spheremap {
namespace {

const char* const kPointCloud = "the file is a point cloud (";

// The failures the CLI and the API refuse a mesh read from a file with.
std::vector<ValidationFailure> failures_of(PolygonMesh input) {
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  return input_failures(prepared, nullptr);
}

void expect_point_cloud(const std::vector<ValidationFailure>& failures, size_t points) {
  ASSERT_FALSE(failures.empty());
  EXPECT_EQ(failures.front().check, "empty");
  EXPECT_EQ(failures.front().message, std::string(kPointCloud) + std::to_string(points) +
                                          " points, no faces): spheremap maps triangle surfaces");
}

TEST(PointCloud, ObjOfVertexLinesOnly) {
  expect_point_cloud(failures_of(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n")), 4);
}

// OBJ `p` elements are points: the file is a point cloud like one of `v` lines only.
TEST(PointCloud, ObjOfPointElements) {
  expect_point_cloud(failures_of(parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n")), 3);
}

// `l` polylines and no faces: said as lines, with their segments counted (a polyline of
// n points is n - 1 segments), under the check a mesh without faces fails.
TEST(PointCloud, ObjOfLinesIsNotCalledOne) {
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nl 1 2\nl 1 2 3 4 1\nl 4\np 1 2\n";
  try {
    parse_obj(obj);
    ADD_FAILURE() << "an OBJ of lines was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "empty");
    EXPECT_EQ(std::string(e.what()),
              "the file has 4 vertices and 5 line segments, no faces: spheremap maps triangle "
              "surfaces");
  }
  // With faces, lines are skipped as before.
  EXPECT_EQ(parse_obj(obj + "f 1 2 3\n").face_count(), 1u);
}

TEST(PointCloud, PlyWithZeroFaces) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  expect_point_cloud(failures_of(parse_ply(ply)), 3);
}

TEST(PointCloud, PlyWithoutAFaceElement) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  try {
    parse_ply(ply);
    ADD_FAILURE() << "a PLY without faces was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "empty");  // as the other formats' (it was "parse": 400)
    EXPECT_NE(std::string(e.what()).find(std::string(kPointCloud) +
                                         "3 points, no 'face' or 'tristrips' element)"),
              std::string::npos)
        << e.what();
  }
}

// Counts of one are said in the singular: "1 point", "1 line segment", not "1 points".
TEST(PointCloud, CountsOfOneAreSingular) {
  try {
    parse_ply(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n");
    ADD_FAILURE() << "a PLY of one point was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(1 point, no 'face'"), std::string::npos) << e.what();
  }
  try {
    parse_obj("v 0 0 0\nv 1 0 0\nl 1 2\n");
    ADD_FAILURE() << "an OBJ of one line segment was read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "the file has 2 vertices and 1 line segment, no faces: spheremap maps triangle "
              "surfaces");
  }
}

TEST(PointCloud, GltfOfPointsPrimitives) {
  testing::Glb glb(testing::sphere_glb());  // icosphere(1): 42 vertices
  for (auto& primitive : glb.json["meshes"][0]["primitives"]) {
    primitive["mode"] = 0;
    primitive.erase("indices");
  }
  try {
    read_gltf(testing::as_bytes(glb.bytes()));
    ADD_FAILURE() << "a glTF of points was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "empty");  // as an OBJ's: nothing to map, not a malformed file
    EXPECT_NE(std::string(e.what()).find(std::string(kPointCloud) + "42 points"), std::string::npos)
        << e.what();
  }
}

TEST(PointCloud, GltfOfLinesIsNotCalledOne) {
  testing::Glb glb(testing::sphere_glb());
  glb.json["meshes"][0]["primitives"][0]["mode"] = 1;
  try {
    read_gltf(testing::as_bytes(glb.bytes()));
    ADD_FAILURE() << "a glTF of lines was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "empty");
    EXPECT_EQ(std::string(e.what()).find("point cloud"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no triangles to map"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace spheremap
