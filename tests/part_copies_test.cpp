// Parts that are copies of an earlier part (part_copies.h) reuse its map, turned.
#include "core/map/part_copies.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "core/map/certification.h"
#include "core/map/map_check.h"
#include "core/map/pipeline.h"
#include "core/outputs/report_json.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// The rotation by `radians` about the unit axis (Rodrigues).
Rotation turn(Vec3 axis, double radians) {
  axis = axis * (1 / norm(axis));
  const double c = std::cos(radians), s = std::sin(radians), t = 1 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y, t * x * y + s * z, t * y * y + c,
          t * y * z - s * x, t * x * z - s * y, t * y * z + s * x, t * z * z + c};
}

// An asymmetric closed genus-0 part: a sphere with three limbs of different lengths.
PolygonMesh limbs() {
  const std::vector<Vec3> directions = {{1, 0, 0}, {0, 1, 0.3}, {-0.4, -0.2, 1}};
  return testing::with_limbs(testing::icosphere(3), directions, 1.5, 0.35);
}

PolygonMesh moved(PolygonMesh mesh, const Rotation& r, double scale, const Vec3& offset) {
  for (Vec3& p : mesh.positions) p = rotate(r, p) * scale + offset;
  return mesh;
}

TEST(PartCopies, FindsTheRotationOfATurnedScaledMovedCopyAndNoneForAMirrorOrAnotherShape) {
  const PolygonMesh part = limbs();
  const Rotation r = turn({1, 2, 3}, 0.7);
  const PolygonMesh copy = moved(part, r, 2.5, {10, -3, 4});
  const std::optional<Rotation> found = rotation_onto(part.positions, copy.positions, 1e-9);
  ASSERT_TRUE(found);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR((*found)[i], r[i], 1e-12);

  PolygonMesh mirror = copy;
  for (Vec3& p : mirror.positions) p.x = -p.x;
  EXPECT_FALSE(rotation_onto(part.positions, mirror.positions, 1e-5));

  PolygonMesh bent = copy;
  bent.positions[7] += Vec3{0.01, 0, 0};  // one vertex off by 1e-3 of the part's size
  EXPECT_FALSE(rotation_onto(part.positions, bent.positions, 1e-5));
  EXPECT_TRUE(rotation_onto(part.positions, bent.positions, 1e-2));
}

// Copies are looked for among parts of the same faces and shape_hash: a copy's hash is its
// original's (turned, scaled, moved, and rounded as a text file writes it), while
// triangles of other shapes spread over many hashes (47,000 doubled triangles of one
// faces_hash were each fitted against every earlier one).
TEST(PartCopies, AShapeHashIsACopysAndSpreadsOtherShapes) {
  const PolygonMesh part = limbs();
  PolygonMesh copy = moved(part, turn({1, 2, 3}, 0.7), 2.5, {10, -3, 4});
  for (Vec3& p : copy.positions)
    for (double* x : {&p.x, &p.y, &p.z}) *x = std::round(*x * 1e6) / 1e6;  // "%.6f"
  EXPECT_EQ(shape_hash(part.positions), shape_hash(copy.positions));
  std::mt19937 random(5);
  std::uniform_real_distribution<> unit(0, 1);
  std::set<uint64_t> hashes;
  for (int k = 0; k < 1000; ++k) {
    const std::vector<Vec3> triangle = {{unit(random), unit(random), unit(random)},
                                        {unit(random), unit(random), unit(random)},
                                        {unit(random), unit(random), unit(random)}};
    hashes.insert(shape_hash(triangle));
  }
  EXPECT_GT(hashes.size(), 900u);
}

TEST(PartCopies, ACopyReusesItsOriginalsMapTurnedAndIsCertifiedWithTheSameDistortion) {
  const PolygonMesh part = limbs();
  const Rotation r = turn({-1, 0.5, 2}, 2.1);
  PolygonMesh mirror = part;
  for (Vec3& p : mirror.positions) p.x = -p.x;
  mirror = testing::reversed(mirror);  // a mirror image, kept outward: not a copy
  PolygonMesh input = testing::assembled(
      {{part, {0, 0, 0}}, {moved(part, r, 0.5, {}), {8, 0, 0}}, {mirror, {0, 8, 0}}});
  PreparedMesh prepared = prepare_input(input, nullptr, {});
  ASSERT_EQ(prepared.parts.size(), 3u);
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 3u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const MappedPart &original = mapped.parts[0], &copy = mapped.parts[1], &other = mapped.parts[2];
  EXPECT_FALSE(original.copy_of);
  ASSERT_TRUE(copy.copy_of);
  EXPECT_EQ(*copy.copy_of, 0u);
  EXPECT_FALSE(other.copy_of);  // mapped anew
  ASSERT_EQ(copy.mapped.map.sphere.size(), original.mapped.map.sphere.size());
  for (size_t v = 0; v < copy.mapped.map.sphere.size(); ++v)
    EXPECT_LT(norm(copy.mapped.map.sphere[v] - rotate(r, original.mapped.map.sphere[v])), 1e-9);
  EXPECT_TRUE(certify(copy.mapped, copy.mapped.float32_check).certified);
  EXPECT_NEAR(copy.mapped.quality.stretch_l2, original.mapped.quality.stretch_l2, 1e-9);
  EXPECT_EQ(copy.mapped.map.iterations, 0u);  // no map was made for it
  EXPECT_GT(original.mapped.map.iterations + original.mapped.map.stretch_vertex_updates, 0);
  // The search and the fit take time no map stage had, and the report says how much.
  EXPECT_GT(mapped.map.copies_seconds, 0.0);

  const nlohmann::json metrics = metrics_json(mapped, {});
  ASSERT_EQ(metrics["parts"].size(), 3u);
  size_t copies = 0;
  for (const auto& p : metrics["parts"])
    if (p.contains("copy_of")) {
      ++copies;
      EXPECT_EQ(metrics["parts"][p["copy_of"].get<size_t>()]["faces"], p["faces"]);
      EXPECT_FALSE(metrics["parts"][p["copy_of"].get<size_t>()].contains("copy_of"));
    }
  EXPECT_EQ(copies, 1u);
  EXPECT_EQ(metrics["seconds"]["copies"].get<double>(), mapped.map.copies_seconds);
}

}  // namespace
}  // namespace spheremap
