// Raw Draco files (.drc): read back what the Draco encoder wrote, refuse what is truncated,
// forged or a point cloud with a clear error.
#include <gtest/gtest.h>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/point_cloud/point_cloud.h>

#include <cstdio>
#include <fstream>

#include "core/io/draco_file.h"
#include "core/io/mesh_file.h"
#include "core/io/mesh_format.h"
#include "core/mesh/input_error.h"
#include "tests/draco_writer.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

std::span<const uint8_t> as_bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The check and message read_draco_file refuses `drc` with ("read" when it is read).
struct Refusal {
  std::string check, message;
};
Refusal refusal(const std::string& drc, const MeshLimits& limits = {}) {
  try {
    read_draco_file(as_bytes(drc), limits);
  } catch (const InputError& e) {
    return {e.check(), e.what()};
  }
  return {"read", ""};
}

Vec3 rounded(const Vec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

TEST(DracoFile, SequentialEncodingReadsBackEqual) {
  const PolygonMesh mesh = testing::icosphere(2);
  const std::string drc = testing::drc_bytes(mesh, draco::MESH_SEQUENTIAL_ENCODING);
  const PolygonMesh read = read_draco_file(as_bytes(drc));
  ASSERT_EQ(read.vertex_count(), mesh.vertex_count());
  EXPECT_EQ(read.offsets, mesh.offsets);
  EXPECT_EQ(read.indices, mesh.indices);
  // float32 as stored: the same floats as the mesh's positions rounded.
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3 expected = rounded(mesh.positions[v]);
    EXPECT_EQ(float(read.positions[v].x), float(expected.x)) << v;
    EXPECT_EQ(float(read.positions[v].y), float(expected.y)) << v;
    EXPECT_EQ(float(read.positions[v].z), float(expected.z)) << v;
  }
}

TEST(DracoFile, EdgebreakerEncodingReadsBackTheSameTriangles) {
  const PolygonMesh mesh = testing::icosphere(2);
  const std::string drc = testing::drc_bytes(mesh, draco::MESH_EDGEBREAKER_ENCODING);
  const PolygonMesh read = read_draco_file(as_bytes(drc));
  ASSERT_EQ(read.face_count(), mesh.face_count());
  // Edgebreaker renumbers: the same triangles by their corners' positions, as sets.
  auto corner_sets = [](const PolygonMesh& m) {
    std::vector<std::array<float, 9>> out;
    for (size_t f = 0; f < m.face_count(); ++f) {
      std::array<std::array<float, 3>, 3> c;
      for (size_t k = 0; k < 3; ++k) {
        const Vec3 p = rounded(m.positions[m.face(f)[k]]);
        c[k] = {float(p.x), float(p.y), float(p.z)};
      }
      // Rotated so the smallest corner leads (keeps the orientation).
      const size_t first = std::min_element(c.begin(), c.end()) - c.begin();
      std::array<float, 9> t;
      for (size_t k = 0; k < 3; ++k)
        for (size_t i = 0; i < 3; ++i) t[3 * k + i] = c[(first + k) % 3][i];
      out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(corner_sets(read), corner_sets(mesh));
}

TEST(DracoFile, SniffedByMagicAndReadByExtension) {
  const PolygonMesh mesh = testing::icosphere(1);
  const std::string drc = testing::drc_bytes(mesh, draco::MESH_EDGEBREAKER_ENCODING);
  EXPECT_EQ(sniff_mesh_format(drc), MeshFormat::kDrc);
  EXPECT_EQ(format_from_extension("DRC"), MeshFormat::kDrc);
  EXPECT_EQ(parse_mesh_text(drc, MeshFormat::kDrc).face_count(), mesh.face_count());
  const std::string path = ::testing::TempDir() + "draco_file_test.drc";
  std::ofstream(path, std::ios::binary) << drc;
  EXPECT_EQ(read_mesh_file(path).face_count(), mesh.face_count());
  std::remove(path.c_str());
}

// Every truncation of the file: a clear error, never a crash (the sanitized build checks).
TEST(DracoFile, TruncatedFilesAreRefused) {
  for (auto method : {draco::MESH_SEQUENTIAL_ENCODING, draco::MESH_EDGEBREAKER_ENCODING}) {
    const std::string drc = testing::drc_bytes(testing::icosphere(1), method);
    for (size_t size = 0; size < drc.size(); ++size) {
      const Refusal cut = refusal(drc.substr(0, size));
      EXPECT_EQ(cut.check, "parse") << size << " of " << drc.size() << ": " << cut.message;
      EXPECT_EQ(cut.message.rfind("drc: ", 0), 0u) << cut.message;
    }
  }
}

// The sequential header: "DRACO", version 2.2, mesh, method 0, flags (2 bytes), then the
// faces and the points as LEB128 varints.
std::string with_counts(const std::string& drc, uint64_t faces, uint64_t points) {
  auto varint = [](uint64_t v) {
    std::string out;
    do {
      out.push_back(static_cast<char>((v & 0x7f) | (v >= 0x80 ? 0x80 : 0)));
      v >>= 7;
    } while (v);
    return out;
  };
  size_t at = 11;  // past the header: skip the two varints
  for (int k = 0; k < 2; ++k)
    while (static_cast<uint8_t>(drc[at++]) & 0x80) {
    }
  return drc.substr(0, 11) + varint(faces) + varint(points) + drc.substr(at);
}

TEST(DracoFile, ForgedCountsAreRefusedBeforeDecoding) {
  const PolygonMesh mesh = testing::icosphere(1);
  const std::string drc = testing::drc_bytes(mesh, draco::MESH_SEQUENTIAL_ENCODING);
  ASSERT_EQ(with_counts(drc, mesh.face_count(), mesh.vertex_count()), drc);
  // Draco would allocate by these (4 billion faces): refused by the header alone.
  const Refusal forged = refusal(with_counts(drc, 0xFFFFFFFFu, mesh.vertex_count()));
  EXPECT_EQ(forged.check, "too_large");
  EXPECT_NE(forged.message.find("4294967295"), std::string::npos) << forged.message;
  // Within the caps but past the data: a decoding error.
  EXPECT_THROW(read_draco_file(as_bytes(with_counts(drc, 100000, 100000))), InputError);
  // The caller's limits.
  MeshLimits limits;
  limits.max_triangles = mesh.face_count() - 1;
  EXPECT_EQ(refusal(drc, limits).check, "too_large");
}

// The fuzzer's find: a tetrahedron whose POSITION data type was changed to bool (byte 29,
// 9 -> 11). Draco converts bool values by loading bytes as bool (undefined behaviour for
// 128, which the sanitized build reports): refused before converting.
TEST(DracoFile, BoolPositionsAreRefused) {
  std::string drc;
  const std::string hex =
      "445241434f0202010000000404010001020003010002030103020101000b030000000000803f00003f3f"
      "000080800000803f000080bf010080bf000080bf0000803f000080bf000080bf000080bf0000803f";
  for (size_t k = 0; k < hex.size(); k += 2)
    drc.push_back(static_cast<char>(std::stoi(hex.substr(k, 2), nullptr, 16)));
  const Refusal bool_positions = refusal(drc);
  EXPECT_EQ(bool_positions.check, "parse");
  EXPECT_NE(bool_positions.message.find("not numeric"), std::string::npos)
      << bool_positions.message;
}

TEST(DracoFile, APointCloudIsRefusedAsOne) {
  const std::string drc = testing::drc_point_cloud_bytes(testing::icosphere(1).positions);
  EXPECT_EQ(sniff_mesh_format(drc), MeshFormat::kDrc);
  const Refusal cloud_refusal = refusal(drc);
  EXPECT_EQ(cloud_refusal.check, "empty");
  EXPECT_NE(cloud_refusal.message.find("is a point cloud (42 points, no faces)"), std::string::npos)
      << cloud_refusal.message;
}

// A point cloud whose header is cut short: the header reader's message is wrapped once
// ("drc: the Draco stream ends inside its header"), with one prefix, as every other.
TEST(DracoFile, ATruncatedPointCloudHeaderIsToldWithOnePrefix) {
  const std::string drc = testing::drc_point_cloud_bytes(testing::icosphere(1).positions);
  EXPECT_EQ(refusal(drc.substr(0, 9)).message, "drc: the Draco stream ends inside its header");
  for (size_t size = 8; size < drc.size(); ++size) {
    const Refusal cut = refusal(drc.substr(0, size));
    if (cut.check == "empty") continue;  // the header, which holds the count, is whole
    EXPECT_EQ(cut.check, "parse") << size << ": " << cut.message;
    EXPECT_EQ(cut.message.rfind("drc: the Draco stream ", 0), 0u) << cut.message;
    EXPECT_EQ(cut.message.find("drc:", 1), std::string::npos) << cut.message;
  }
}

}  // namespace
}  // namespace spheremap
