#include <gtest/gtest.h>

#include <functional>

#include <cstring>
#include <nlohmann/json.hpp>

#include "core/io/glb_writer.h"
#include "core/io/gltf_reader.h"
#include "core/io/mesh_file.h"
#include "core/io/text_reader.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"
#include "core/mesh/sphere_geometry.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_glb.h"
#include "tests/corpus.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using testing::as_bytes;
using testing::Glb;
using testing::read_error;
using testing::sphere_glb;

TEST(Gltf, WrittenGlbReadsBackExactly) {
  const PolygonMesh m = testing::icosphere(1);
  const PolygonMesh back = read_gltf(as_bytes(sphere_glb()));
  ASSERT_EQ(back.vertex_count(), m.vertex_count());
  std::vector<uint32_t> expected;
  for (const Triangle& t : fan_triangulate(m).triangles)
    expected.insert(expected.end(), t.begin(), t.end());
  EXPECT_EQ(back.indices, expected);
  for (size_t v = 0; v < m.vertex_count(); ++v)
    EXPECT_NEAR(norm(back.positions[v] - m.positions[v]), 0, 1e-7);
  const Glb glb(sphere_glb());
  EXPECT_EQ(glb.json["meshes"][0]["extras"]["note"], "test");
  EXPECT_EQ(glb.json["accessors"][0]["min"].size(), 3u);
}

// glTF stores float32: a position past its range would be written as infinity (an invalid
// file with null bounds, which the writer used to produce with exit 0).
TEST(Gltf, RefusesToWritePositionsBeyondFloat32) {
  const PolygonMesh m = testing::icosphere(1);
  GlbMesh mesh;
  mesh.positions = m.positions;
  mesh.triangles = fan_triangulate(m).triangles;
  EXPECT_NO_THROW(format_glb(mesh));
  mesh.positions[3].y = 1e150;
  try {
    format_glb(mesh);
    FAIL() << "wrote a position of 1e150 as float32";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "float32_range");
    EXPECT_NE(std::string(e.what()).find("1e+150"), std::string::npos) << e.what();
  }
}

// ... and a mesh whose every coordinate is below float32's smallest normal would be stored
// as a point (the writer wrote zeros with exit 0); tiny but normal units are kept.
TEST(Gltf, RefusesToWritePositionsBelowFloat32) {
  const PolygonMesh m = testing::icosphere(1);
  GlbMesh mesh;
  mesh.triangles = fan_triangulate(m).triangles;
  for (const Vec3& p : m.positions) mesh.positions.push_back(p * 1e-30);
  EXPECT_NO_THROW(format_glb(mesh));
  for (Vec3& p : mesh.positions) p = p * 1e-270;
  try {
    format_glb(mesh);
    FAIL() << "wrote a mesh at 1e-300 as float32";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "float32_range");
    EXPECT_NE(std::string(e.what()).find("smallest normal"), std::string::npos) << e.what();
  }
}

TEST(Gltf, RejectsTruncatedFilesAtEveryLength) {
  const std::string file = sphere_glb();
  for (size_t cut :
       {size_t{0}, size_t{3}, size_t{11}, size_t{19}, size_t{40}, file.size() / 2, file.size() - 1})
    EXPECT_FALSE(read_error(file.substr(0, cut)).empty()) << "cut at " << cut;
}

TEST(Gltf, RejectsWrongChunkAndHeaderLengths) {
  std::string file = sphere_glb();
  std::string longer = file;
  const uint32_t huge = 1u << 30;
  std::memcpy(longer.data() + 12, &huge, 4);  // JSON chunk length
  EXPECT_NE(read_error(longer).find("past the end"), std::string::npos);
  std::memcpy(file.data() + 8, &huge, 4);  // total length
  EXPECT_NE(read_error(file).find("declares"), std::string::npos);
}

TEST(Gltf, RejectsRangesPastTheirData) {
  Glb glb(sphere_glb());
  glb.json["bufferViews"][0]["byteLength"] = 1 << 20;
  EXPECT_NE(read_error(glb.bytes()).find("runs past its buffer"), std::string::npos);
  Glb counts(sphere_glb());
  counts.json["accessors"][0]["count"] = 4000000000u;  // huge declared count
  EXPECT_NE(read_error(counts.bytes()).find("runs past its bufferView"), std::string::npos);
  Glb offset(sphere_glb());
  offset.json["accessors"][0]["byteOffset"] = 1u << 31;
  EXPECT_NE(read_error(offset.bytes()).find("runs past"), std::string::npos);
  Glb view(sphere_glb());
  view.json["accessors"][0]["bufferView"] = 17;
  EXPECT_NE(read_error(view.bytes()).find("accessor 0 refers to bufferView 17, but the file has"),
            std::string::npos);
}

// tinygltf's BoundsChecking files, as small as they go: each dangling reference is told
// where it is resolved, with the index and the count, and ahead of the missing POSITION
// (all of them lack one).
TEST(Gltf, TellsOutOfRangeReferencesWhereTheyAreResolved) {
  auto file = [](const std::string& buffers, const std::string& view, const std::string& accessor,
                 const std::string& primitive) {
    return R"({"asset":{"version":"2.0"},"buffers":[)" + buffers + R"(],"bufferViews":[)" + view +
           R"(],"accessors":[)" + accessor + R"(],"meshes":[{"primitives":[)" + primitive + "]}]}";
  };
  const std::string buffer = R"({"byteLength":6,"uri":"data:;base64,AAABAAIA"})";
  const std::string view = R"({"buffer":0,"byteLength":6})";
  const std::string indices = R"({"bufferView":0,"componentType":5123,"count":3,"type":"SCALAR"})";
  const std::string no_position = R"({"attributes":{},"indices":0})";
  EXPECT_EQ(read_error(file(buffer, view, indices, no_position)),
            "mesh 0 primitive 0 has no POSITION attribute");
  EXPECT_EQ(read_error(file("", view,
                            R"({"bufferView":1,"componentType":5123,"count":3,)"
                            R"("type":"SCALAR"})",
                            no_position)),
            "accessor 0 refers to bufferView 1, but the file has 1 bufferView");
  EXPECT_EQ(read_error(file("", view, indices, R"({"attributes":{},"indices":1})")),
            "mesh 0 primitive 0 refers to accessor 1 as its indices, but the file has 1 accessor");
  EXPECT_EQ(read_error(file(buffer, R"({"buffer":1,"byteLength":6})", indices, no_position)),
            "bufferView 0 refers to buffer 1, but the file has 1 buffer");
  EXPECT_EQ(read_error(file("", view, indices, no_position)),
            "bufferView 0 refers to buffer 0, but the file has no buffers");
  EXPECT_EQ(read_error(file(buffer, view, indices, R"({"attributes":{"POSITION":5}})")),
            "mesh 0 primitive 0 refers to accessor 5 as its POSITION, but the file has 1 accessor");
  EXPECT_EQ(read_error(file(buffer, view, indices, R"({"attributes":{},"indices":-1})")),
            "mesh 0 primitive 0 refers to accessor -1 as its indices, which is not an index");
}

// A count or a byte range that is not an integer is told with its real bound, never with
// a sentinel ("1e+300 is out of range (18446744073709551615 available)").
TEST(Gltf, TellsNonIntegerSizesWithTheirRealBound) {
  auto file = [](const std::string& view, const std::string& count) {
    return R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":6,)"
           R"("uri":"data:;base64,AAABAAIA"}],"bufferViews":[)" +
           view + R"(],"accessors":[{"bufferView":0,"componentType":5123,"count":)" + count +
           R"(,"type":"SCALAR"}],"meshes":[{"primitives":[{"attributes":{},"indices":0}]}]})";
  };
  const std::string too_long = read_error(file(R"({"buffer":0,"byteLength":1e300})", "3"));
  EXPECT_EQ(too_long,
            "bufferView 0's byteLength 1e+300 is not a byte count (an integer from 0 to 6, the "
            "size of buffer 0)");
  EXPECT_EQ(read_error(file(R"({"buffer":0,"byteOffset":-2,"byteLength":6})", "3")),
            "bufferView 0's byteOffset -2 is not a byte offset (an integer from 0 to 6, the size "
            "of buffer 0)");
  EXPECT_EQ(read_error(file(R"({"buffer":0,"byteLength":6})", "1.5")),
            "accessor 0's count 1.5 is not an element count (a non-negative integer)");
  // The largest integer is a byte count, past the buffer: not "no byteLength".
  EXPECT_NE(read_error(file(R"({"buffer":0,"byteLength":18446744073709551615})", "3"))
                .find("runs past its buffer of 6 bytes"),
            std::string::npos);
}

// POSITION is not required of a primitive (one without it draws nothing): such primitives
// beside drawn ones are skipped with a warning (magnum's mesh.glb was refused whole); a file
// with no other primitive is refused, naming the first.
TEST(Gltf, SkipsPrimitivesWithoutPositionBesideDrawnOnes) {
  const PolygonMesh plain = read_gltf(as_bytes(sphere_glb()));
  Glb glb(sphere_glb());
  glb.json["meshes"][0]["primitives"].push_back({{"attributes", nlohmann::json::object()}});
  glb.json["meshes"][0]["primitives"].push_back(
      {{"attributes", {{"NORMAL", 0}}},
       {"indices", glb.json["meshes"][0]["primitives"][0]["indices"]}});
  GltfReadStats stats;
  const PolygonMesh read = read_gltf(as_bytes(glb.bytes()), {}, &stats);
  EXPECT_EQ(read.indices, plain.indices);
  EXPECT_EQ(read.positions, plain.positions);
  EXPECT_EQ(stats.primitives, 1u);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_EQ(stats.warnings[0],
            "mesh 0 primitive 1 has no POSITION attribute (nor 1 more primitives): skipped, as "
            "viewers skip it (it draws nothing)");
  glb.json["meshes"][0]["primitives"].erase(0);
  EXPECT_EQ(read_error(glb.bytes()),
            "mesh 0 primitive 0 has no POSITION attribute (nor 1 more primitives)");
}

// byteStride 0 is not valid glTF, but exporters write it meaning "packed" and viewers read
// it so: read as packed, with a warning in the stats and the topology report.
TEST(Gltf, ReadsByteStrideZeroAsPackedWithAWarning) {
  const PolygonMesh plain = read_gltf(as_bytes(sphere_glb()));
  Glb glb(sphere_glb());
  glb.json["bufferViews"][2]["byteStride"] = 0;  // the indices
  glb.json["bufferViews"][0]["byteStride"] = 0;  // the positions
  GltfReadStats stats;
  const PolygonMesh read = read_gltf(as_bytes(glb.bytes()), {}, &stats);
  EXPECT_EQ(read.indices, plain.indices);
  EXPECT_EQ(read.positions, plain.positions);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_EQ(stats.warnings[0],
            "byteStride 0 (not valid glTF) read as tightly packed in 2 bufferViews (0, 2)");
  const nlohmann::json report = topology_json(prepare_mesh(read, {}), &stats);
  EXPECT_EQ(report["warnings"], stats.warnings);
  EXPECT_TRUE(report["mappable"].get<bool>());
  // Without leniency there is no "warnings" key at all.
  GltfReadStats clean;
  read_gltf(as_bytes(sphere_glb()), {}, &clean);
  EXPECT_FALSE(topology_json(prepare_mesh(plain, {}), &clean).contains("warnings"));
  // A stride that is not 0 but too small still overlaps its elements.
  glb.json["bufferViews"][2]["byteStride"] = 2;
  EXPECT_NE(read_error(glb.bytes()).find("elements overlap"), std::string::npos);
}

// Appends `bytes` to the GLB's binary chunk (4-byte aligned) as a new bufferView; its index.
size_t append_view(Glb& glb, const std::string& bytes) {
  while (glb.bin.size() % 4) glb.bin.push_back('\0');
  nlohmann::json view = {
      {"buffer", 0}, {"byteOffset", glb.bin.size()}, {"byteLength", bytes.size()}};
  glb.bin += bytes;
  glb.json["buffers"][0]["byteLength"] = glb.bin.size();
  glb.json["bufferViews"].push_back(view);
  return glb.json["bufferViews"].size() - 1;
}

// KhronosGroup's SimpleSparseAccessor (in the Draco test data) was refused ("sparse
// accessors are not supported"): the listed elements replace the bufferView's, or zeros.
TEST(Gltf, ReadsSparseAccessorsOverAViewAndOverZeros) {
  const PolygonMesh plain = read_gltf(as_bytes(sphere_glb()));
  const size_t n = plain.vertex_count();
  Glb glb(sphere_glb());
  const size_t position = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  nlohmann::json& accessor = glb.json["accessors"][position];
  const size_t view = accessor["bufferView"];
  const size_t at =
      glb.json["bufferViews"][view].value("byteOffset", 0) + accessor.value("byteOffset", 0);
  auto positions_of = [&](std::initializer_list<uint32_t> list) {
    std::string out;
    for (uint32_t v : list) out += glb.bin.substr(at + 12 * v, 12);
    return out;
  };
  // Over the view: vertices 3 and 7 are wrong in it, right in the sparse values.
  const std::string values = positions_of({3, 7});
  std::memset(glb.bin.data() + at + 12 * 3, 0x7f, 12);
  std::memset(glb.bin.data() + at + 12 * 7, 0x7f, 12);
  const uint16_t where[2] = {3, 7};
  const size_t where_view = append_view(glb, std::string(reinterpret_cast<const char*>(where), 4));
  const size_t values_view = append_view(glb, values);
  accessor["sparse"] = {{"count", 2},
                        {"indices", {{"bufferView", where_view}, {"componentType", 5123}}},
                        {"values", {{"bufferView", values_view}}}};
  EXPECT_EQ(read_gltf(as_bytes(glb.bytes())).positions, plain.positions);
  // Not increasing, and past the accessor: refused, naming the accessor.
  const uint16_t backwards[2] = {7, 3};
  std::memcpy(glb.bin.data() + glb.json["bufferViews"][where_view]["byteOffset"].get<size_t>(),
              backwards, 4);
  EXPECT_NE(read_error(glb.bytes()).find("not increasing"), std::string::npos);
  accessor["sparse"]["count"] = n + 1;
  EXPECT_NE(read_error(glb.bytes()).find("sparse.count"), std::string::npos);
  accessor["sparse"]["count"] = 2;
  accessor["sparse"]["values"]["byteOffset"] = 4;
  EXPECT_NE(read_error(glb.bytes()).find("sparse.values"), std::string::npos);
  // Over zeros: no bufferView, every vertex in the sparse values.
  Glb zeros(sphere_glb());
  nlohmann::json& dense = zeros.json["accessors"][position];
  std::string all = zeros.bin.substr(at, 12 * n), indices;
  for (uint32_t v = 0; v < n; ++v) indices.append(reinterpret_cast<const char*>(&v), 4);
  dense.erase("bufferView");
  dense.erase("byteOffset");
  const size_t index_view = append_view(zeros, indices);
  dense["sparse"] = {{"count", n},
                     {"indices", {{"bufferView", index_view}, {"componentType", 5125}}},
                     {"values", {{"bufferView", append_view(zeros, all)}}}};
  EXPECT_EQ(read_gltf(as_bytes(zeros.bytes())).positions, plain.positions);
}

// A field bounded by the spec is told with its range, never as "(253 available)" as if the
// file had 253 of something; an index past a count names who refers to it.
TEST(Gltf, TellsBoundsAsRangesAndReferencesByReferrer) {
  auto error_after = [](const std::function<void(Glb&)>& edit) {
    Glb glb(sphere_glb());
    edit(glb);
    return read_error(glb.bytes());
  };
  auto position_of = [](Glb& glb) -> nlohmann::json& {
    const size_t position = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    return glb.json["accessors"][position];
  };
  EXPECT_NE(error_after([&](Glb& glb) {
              glb.json["bufferViews"][position_of(glb)["bufferView"].get<size_t>()]["byteStride"] =
                  253;
            }).find("'s byteStride 253 is not an integer from 0 to 252"),
            std::string::npos);
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["meshes"][0]["primitives"][0]["mode"] = 7; }),
            "mesh 0 primitive 0's mode 7 is not an integer from 0 to 6");
  // The bound of sparse.count is compared, not computed: no "(0 available)" from an overflow.
  const std::string sparse_count = error_after([&](Glb& glb) {
    nlohmann::json& accessor = position_of(glb);
    accessor["sparse"] = {{"count", UINT64_MAX},
                          {"indices", {{"bufferView", 0}, {"componentType", 5125}}},
                          {"values", {{"bufferView", 0}}}};
    accessor["count"] = UINT64_MAX;
  });
  EXPECT_EQ(sparse_count.find("available"), std::string::npos) << sparse_count;
  const std::string sparse_over = error_after([&](Glb& glb) {
    position_of(glb)["sparse"] = {{"count", UINT64_MAX},
                                  {"indices", {{"bufferView", 0}, {"componentType", 5125}}},
                                  {"values", {{"bufferView", 0}}}};
  });
  EXPECT_NE(sparse_over.find("'s sparse.count 18446744073709551615 is not an integer from 1 to " +
                             std::to_string(read_gltf(as_bytes(sphere_glb())).vertex_count()) +
                             " (its count)"),
            std::string::npos)
      << sparse_over;
  const std::string sparse_type = error_after([&](Glb& glb) {
    position_of(glb)["sparse"] = {{"count", 1},
                                  {"indices", {{"bufferView", 0}, {"componentType", 6000}}},
                                  {"values", {{"bufferView", 0}}}};
  });
  EXPECT_NE(sparse_type.find("UNSIGNED_INT (5121, 5123 or 5125), not 6000"), std::string::npos)
      << sparse_type;
  const size_t nodes = Glb(sphere_glb()).json["nodes"].size();
  const std::string have =
      "but the file has " + std::to_string(nodes) + (nodes == 1 ? " node" : " nodes");
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["scenes"][0]["nodes"] = {5}; }),
            "scene 0 refers to node 5, " + have);
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["nodes"][0]["children"] = {5}; }),
            "node 0's children refer to node 5, " + have);
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["nodes"][0]["children"] = {"x"}; }),
            "node 0's children refer to node \"x\", which is not an index");
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["scene"] = 3; }),
            "the top-level scene field refers to scene 3, but the file has 1 scene");
  EXPECT_EQ(error_after([](Glb& glb) { glb.json["nodes"][0]["mesh"] = 4; }),
            "node 0 refers to mesh 4, but the file has 1 mesh");
}

// An accessor without a bufferView (and without sparse) is zeros (glTF 3.6.2.3); it was
// refused "accessor 0 has no bufferView" (glTF-Validator's KHR_mesh_quantization
// valid.gltf). Its count is bounded by the decode limit, since no bytes bound it.
TEST(Gltf, ReadsAnAccessorWithoutABufferViewAsZeros) {
  const PolygonMesh plain = read_gltf(as_bytes(sphere_glb()));
  Glb glb(sphere_glb());
  const size_t position = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  nlohmann::json& accessor = glb.json["accessors"][position];
  accessor.erase("bufferView");
  accessor.erase("byteOffset");
  const PolygonMesh zeros = read_gltf(as_bytes(glb.bytes()));
  ASSERT_EQ(zeros.vertex_count(), plain.vertex_count());
  EXPECT_EQ(zeros.indices, plain.indices);
  for (const Vec3& p : zeros.positions) EXPECT_EQ(norm(p), 0.0);
  accessor["count"] = uint64_t{1} << 50;
  try {
    read_gltf(as_bytes(glb.bytes()));
    FAIL() << "read 2^50 zero positions";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "too_large") << e.what();
    EXPECT_NE(std::string(e.what()).find("no bufferView"), std::string::npos) << e.what();
  }
}

TEST(Gltf, RejectsIndicesPastTheVertices) {
  Glb glb(sphere_glb());
  const uint32_t past = 1000;
  std::memcpy(glb.bin.data() + glb.json["bufferViews"][2]["byteOffset"].get<size_t>(), &past, 4);
  EXPECT_NE(read_error(glb.bytes()).find("index 1000 at position 0"), std::string::npos);
}

TEST(Gltf, RefusesUrisOutsideTheFolderAndOtherSchemes) {
  const std::pair<const char*, const char*> cases[] = {{"/etc/passwd", "absolute path"},
                                                       {"../../etc/passwd", "'..' segment"},
                                                       {"a/%2E%2E/%2e%2e/x.bin", "'..' segment"},
                                                       {"file:///etc/passwd", "scheme"},
                                                       {"http://example.com/a.bin", "scheme"},
                                                       {"c:\\x.bin", "scheme"},
                                                       {"a\\..\\b.bin", "backslash"},
                                                       {"x%00.bin", "NUL"},
                                                       {"x%4.bin", "two hex digits"},
                                                       {"data:text/plain,abc", "not base64"}};
  for (const auto& [uri, why] : cases) {
    Glb glb(sphere_glb());
    glb.json["buffers"][0]["uri"] = uri;
    EXPECT_NE(read_error(glb.bytes()).find(why), std::string::npos) << uri;
  }
}

TEST(Gltf, ReadsEmbeddedBase64Buffers) {
  Glb glb(sphere_glb());
  glb.json["buffers"][0]["uri"] =
      "data:application/octet-stream;base64," + testing::base64(glb.bin);
  const PolygonMesh m = read_gltf(as_bytes(glb.json.dump()));  // .gltf JSON text
  EXPECT_EQ(m.vertex_count(), testing::icosphere(1).vertex_count());
}

// A buffer with neither uri nor GLB chunk is refused only when a mesh reads it: with no
// meshes (glTF-Validator's accessor/alignment.gltf) the real trouble is nothing to map.
TEST(Gltf, RefusesADatalessBufferOnlyWhenRead) {
  const std::string no_meshes =
      R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":8}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":8}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":2,"type":"SCALAR"}]})";
  EXPECT_NE(read_error(no_meshes).find("the file has no meshes"), std::string::npos);
  Glb needed(sphere_glb());
  needed.json["buffers"][0].erase("uri");
  const std::string error = read_error(needed.json.dump());  // .gltf JSON: no GLB chunk
  EXPECT_NE(error.find("reads buffer 0, which has no data (no uri and no GLB binary chunk)"),
            std::string::npos)
      << error;
}

TEST(Gltf, RejectsFilesWithoutTriangles) {
  EXPECT_NE(read_error(R"({"asset":{"version":"2.0"}})").find("no meshes"), std::string::npos);
  Glb points(sphere_glb());
  points.json["meshes"][0]["primitives"][0]["mode"] = 0;
  EXPECT_NE(read_error(points.bytes(), "empty").find("is a point cloud (42 points, no faces)"),
            std::string::npos);
  points.json["meshes"][0]["primitives"][0]["mode"] = 1;
  EXPECT_NE(read_error(points.bytes(), "empty").find("1 primitive(s) of points or lines"),
            std::string::npos);
  EXPECT_NE(read_error("[1, 2]").find("not glTF: neither a GLB"), std::string::npos);
  EXPECT_NE(read_error("{not json at all").find("does not parse as an object"), std::string::npos);
  // glTF 1.0, however its version is written, is read (gltf1_test.cpp): this one has no meshes.
  for (const char* version : {R"("1.0")", R"("1")", "1", "1.0"})
    EXPECT_NE(read_error(std::string(R"({"asset":{"version":)") + version + "}}").find("no meshes"),
              std::string::npos)
        << version;
  EXPECT_NE(read_error(R"({"asset":{"version":2}})").find("not a glTF 2.0"), std::string::npos);
  EXPECT_NE(read_error(R"({"asset":{"version":"3.0"}})").find("not a glTF 2.0"), std::string::npos);
}

// A file that is not glTF at all says so, and what it starts with (at most 8 bytes).
TEST(Gltf, NamesAnEmptyOrForeignFile) {
  EXPECT_NE(read_error("").find("empty file (0 bytes)"), std::string::npos);
  const std::string png_error = read_error(std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
  EXPECT_NE(png_error.find("not glTF"), std::string::npos) << png_error;
  EXPECT_NE(png_error.find("starts with \"\\x89PNG\\x0d\\x0a\\x1a\\x0a\""), std::string::npos)
      << png_error;
  const std::string obj_error = read_error("v 1 2 3\nv 4 5 6\nf 1 2 3\n");
  EXPECT_NE(obj_error.find("starts with \"v 1 2 3\\x0a\""), std::string::npos) << obj_error;
  EXPECT_LT(read_error(std::string(100000, 'A')).size(), 300u);  // bounded echo
}

TEST(Gltf, AppliesNodeTransformsAndKeepsMirroredWindingOutward) {
  Glb glb(sphere_glb());
  glb.json["nodes"][0]["scale"] = {-2.0, 2.0, 2.0};  // mirror
  glb.json["nodes"][0]["translation"] = {10.0, 0.0, 0.0};
  const PolygonMesh m = read_gltf(as_bytes(glb.bytes()));
  const PreparedMesh p = prepare_mesh(m, {});
  EXPECT_TRUE(mapping_failures(p.topology).empty());
  EXPECT_GT(p.topology.signed_volume, 0);  // still outward after the mirror
  EXPECT_NEAR(m.positions[0].x, 10 - 2 * testing::icosphere(1).positions[0].x, 1e-6);
}

TEST(Gltf, ConvertsStripsAndFans) {
  Glb fan(sphere_glb());
  fan.json["meshes"][0]["primitives"][0]["mode"] = 6;
  EXPECT_GT(read_gltf(as_bytes(fan.bytes())).face_count(), 0u);
  Glb strip(sphere_glb());
  strip.json["meshes"][0]["primitives"][0]["mode"] = 5;
  const size_t strip_triangles = read_gltf(as_bytes(strip.bytes())).face_count();
  EXPECT_GT(strip_triangles, 0u);
  // The expansion is counted against the cap before the triangles are made.
  GltfReadOptions cap;
  cap.max_triangles = strip_triangles - 1;
  try {
    read_gltf(as_bytes(strip.bytes()), cap);
    ADD_FAILURE() << "a strip over the triangle cap was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "too_large");
  }
}

// Nodes form a forest: a cycle, or a node listed by two parents, is refused when the walk
// reaches a node the second time (so the walk is bounded by the node count).
TEST(Gltf, RejectsNodeCyclesAndSharedChildren) {
  Glb cycle(sphere_glb());
  cycle.json["nodes"][0]["children"] = {0};
  EXPECT_NE(read_error(cycle.bytes()).find("reached twice"), std::string::npos);
  Glb shared(sphere_glb());
  shared.json["nodes"] = {{{"children", {1, 1}}}, {{"mesh", 0}}};
  shared.json["scenes"] = {{{"nodes", {0}}}};
  shared.json["scene"] = 0;
  EXPECT_NE(read_error(shared.bytes()).find("node 1 is reached twice"), std::string::npos);
}

// JSON nested deeper than 64 levels is refused while parsing, with the reason.
TEST(Gltf, RejectsDeeplyNestedJson) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const std::string text = R"({"asset":{"version":"2.0"},"scene":)" + deep + "}";
  EXPECT_NE(read_error(text).find("nested deeper than 64"), std::string::npos);
}

// The three crash cases of Debian's tinygltf + Draco, and two more, on a real Draco file.
TEST(GltfDraco, RejectsBrokenDracoReferences) {
  SKIP_WITHOUT_CORPUS("box.draco.glb");
  const std::string file = read_file(testing::corpus_path("box.draco.glb"));
  EXPECT_EQ(read_gltf(as_bytes(file)).face_count(), 12u);
  auto draco = [](Glb& g) -> nlohmann::json& {
    for (auto& p : g.json["meshes"][0]["primitives"])
      if (p.contains("extensions")) return p["extensions"]["KHR_draco_mesh_compression"];
    throw std::runtime_error("no Draco primitive");
  };
  Glb view(file);
  draco(view)["bufferView"] = 99;
  EXPECT_NE(read_error(view.bytes())
                .find("'s KHR_draco_mesh_compression refers to bufferView 99, but the file has"),
            std::string::npos);
  Glb attribute(file);
  draco(attribute)["attributes"]["POSITION"] = 99;
  EXPECT_NE(read_error(attribute.bytes()).find("no 3-component attribute with id 99"),
            std::string::npos);
  Glb offset(file);
  offset.json["bufferViews"][draco(offset)["bufferView"].get<size_t>()]["byteOffset"] = 1u << 30;
  EXPECT_NE(read_error(offset.bytes()).find("runs past its buffer"), std::string::npos);
  Glb garbage(file);
  const size_t at = garbage.json["bufferViews"][draco(garbage)["bufferView"].get<size_t>()].value(
      "byteOffset", 0);
  for (size_t k = 0; k < 64 && at + k < garbage.bin.size(); ++k)
    garbage.bin[at + k] = static_cast<char>(k * 37);
  EXPECT_FALSE(read_error(garbage.bytes()).empty());
}

// A generated Draco GLB (sequential encoding, the stream last in the buffer) whose stream
// `patch` rewrites: the header as Draco writes it is "DRACO", version 2.2, mesh, method,
// flags (2 bytes), then the face and point counts as varints.
std::string patched_draco(const std::function<std::string(const std::string&)>& patch) {
  GlbMesh mesh;
  const PolygonMesh sphere = testing::icosphere(2);
  mesh.positions = sphere.positions;
  mesh.triangles = fan_triangulate(sphere).triangles;
  mesh.draco_position_bits = 14;
  Glb glb(format_glb(mesh));
  const size_t view = glb.json["meshes"][0]["primitives"][0]["extensions"]
                              ["KHR_draco_mesh_compression"]["bufferView"];
  const size_t at = glb.json["bufferViews"][view].value("byteOffset", size_t{0});
  const size_t length = glb.json["bufferViews"][view]["byteLength"];
  const std::string stream = patch(glb.bin.substr(at, length));
  glb.bin = glb.bin.substr(0, at) + stream;
  while (glb.bin.size() % 4) glb.bin.push_back('\0');
  glb.json["bufferViews"][view]["byteLength"] = stream.size();
  glb.json["buffers"][0]["byteLength"] = glb.bin.size();
  return glb.bytes();
}

std::string varint(uint64_t v) {
  std::string out;
  do {
    out.push_back(static_cast<char>((v & 0x7f) | (v > 0x7f ? 0x80 : 0)));
    v >>= 7;
  } while (v);
  return out;
}

// Draco allocates by the counts its header declares; they are read and checked first.
TEST(GltfDraco, DeclaredCountsAreCheckedBeforeDecoding) {
  const std::string plain = patched_draco([](const std::string& s) { return s; });
  EXPECT_EQ(read_gltf(as_bytes(plain)).face_count(), 320u);
  // 320 faces (2 bytes) and 162 points (2 bytes) follow the 11-byte header.
  ASSERT_EQ(plain.size() % 4, 0u);
  const std::string many_points = patched_draco([](const std::string& s) {
    return s.substr(0, 11) + varint(320) + varint(4'000'000'000u) + s.substr(15);
  });
  try {
    read_gltf(as_bytes(many_points));
    ADD_FAILURE() << "4e9 declared points accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "too_large");
    EXPECT_NE(std::string(e.what()).find("declares 4000000000 vertices"), std::string::npos)
        << e.what();
  }
  GltfReadOptions small;
  small.max_triangles = 100;
  EXPECT_THROW(read_gltf(as_bytes(plain), small), InputError);
  const std::string old = patched_draco([](std::string s) {
    s[6] = 1;  // bitstream 2.1
    return s;
  });
  EXPECT_NE(read_error(old).find("version 2.1"), std::string::npos);
  // Metadata nested 1,000 deep (Draco's own reader recurses without a bound).
  const std::string nested = patched_draco([](std::string s) {
    std::string metadata = varint(0);  // no attribute metadata
    for (int depth = 0; depth < 1000; ++depth) metadata += varint(0) + varint(1) + varint(1) + "n";
    s[10] = static_cast<char>(0x80);  // flags: metadata present
    return s.substr(0, 11) + metadata + s.substr(11);
  });
  EXPECT_NE(read_error(nested).find("nests metadata over 16 deep"), std::string::npos);
  // A point cloud stream (bitstream 2.3, type 0, sequential): its header's count is told.
  const std::string cloud = patched_draco([](const std::string&) {
    return std::string("DRACO\x02\x03\x00\x00\x00\x00", 11) + std::string("\xa2\0\0\0", 4);
  });
  EXPECT_NE(read_error(cloud).find("is a point cloud (162 points, no faces)"), std::string::npos)
      << read_error(cloud);
  const std::string cut = patched_draco([](const std::string& s) { return s.substr(0, 12); });
  EXPECT_NE(read_error(cut).find("ends inside its header"), std::string::npos);
}

// The corpus in three forms: the same welded surface from OBJ, GLB and Draco GLB.
class CorpusGltf : public ::testing::TestWithParam<const char*> {};

TEST_P(CorpusGltf, SameWeldedTopologyAsTheObj) {
  const std::string name = GetParam();
  SKIP_WITHOUT_CORPUS(name + ".obj");
  const PreparedMesh obj = prepare_mesh(read_mesh_file(testing::corpus_path(name + ".obj")), {});
  const size_t obj_triangles = fan_triangulate(obj.welded.mesh).triangles.size();
  for (const std::string ext : {".glb", ".draco.glb"}) {
    const PreparedMesh g = prepare_mesh(read_mesh_file(testing::corpus_path(name + ext)), {});
    EXPECT_EQ(g.topology.vertices, obj.topology.vertices) << ext;
    EXPECT_EQ(g.topology.faces, obj_triangles) << ext;
    EXPECT_EQ(g.topology.genus(), 0) << ext;
    EXPECT_TRUE(mapping_failures(g.topology).empty()) << ext;
  }
}

INSTANTIATE_TEST_SUITE_P(Shared, CorpusGltf,
                         ::testing::Values("box", "spot_control", "cylinder", "knight",
                                           "horse_quad", "spot_quad", "duck", "spot", "cheburashka",
                                           "hand", "beast", "armadillo", "horse", "scorpion",
                                           "igea"));

}  // namespace
}  // namespace spheremap

namespace spheremap {
namespace {

TEST(SphereGlb, RoundTripsPlainAndDracoAndJudgesTheDecodedMap) {
  const PolygonMesh sphere = testing::icosphere(3);
  for (int bits : {0, 14}) {
    WrittenGlb file = sphere_glb(sphere, false, bits);
    EXPECT_TRUE(file.check.bijective) << bits << " bits";
    file.glb.json["meshes"][0]["extras"] = {{"k", 1}};
    const std::string bytes = serialize_glb(file.glb);
    const PolygonMesh back = read_gltf(as_bytes(bytes));
    ASSERT_EQ(back.vertex_count(), sphere.vertex_count());  // order kept (sequential Draco)
    const double tolerance = bits ? 2.0 / (1 << bits) : 1e-7;
    for (size_t v = 0; v < sphere.vertex_count(); ++v)
      ASSERT_NEAR(norm(back.positions[v] - sphere.positions[v]), 0, tolerance) << v;
    const Glb glb(bytes);
    EXPECT_EQ(glb.json["meshes"][0]["extras"]["k"], 1);
    EXPECT_EQ(glb.json.contains("extensionsRequired"), bits > 0);
  }
}

TEST(SphereGlb, CatchesAMapThatFoldsOnlyOnceQuantized) {
  // Two corners 1e-9 apart on a valid sphere map: fine in double, gone at 8-bit Draco.
  PolygonMesh sphere = testing::icosphere(2);
  const Triangle t = fan_triangulate(sphere).triangles[0];
  sphere.positions[t[1]] = normalized_or(
      sphere.positions[t[0]] + 1e-9 * (sphere.positions[t[1]] - sphere.positions[t[0]]), {});
  EXPECT_FALSE(sphere_glb(sphere, false, 8).check.bijective);
}

}  // namespace
}  // namespace spheremap
