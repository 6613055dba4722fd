// rescue_float32 (core/map/float32_rescue.h): a map valid in double whose sliver folds or
// collapses once rounded to float32 gets room; a map with nothing failing is unchanged.
#include <gtest/gtest.h>

#include <vector>

#include "core/map/float32_rescue.h"
#include "core/map/map_check.h"
#include "core/mesh/mesh.h"
#include "core/mesh/sphere_geometry.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

bool clean(const MapCheck& check) {
  return check.bijective && check.degenerate == 0;
}

struct Map {
  std::vector<Vec3> sphere;
  std::vector<Triangle> triangles;
};

// The unit icosphere as its own map (outward faces: positive determinants).
Map identity_map() {
  const PolygonMesh mesh = testing::icosphere(3);
  Map map{mesh.positions, fan_triangulate(mesh).triangles};
  for (Vec3& p : map.sphere) p = normalized_or(p, Vec3{0, 0, 1});
  return map;
}

TEST(Float32Rescue, ASliverThatFoldsInFloat32GetsRoom) {
  Map map = identity_map();
  ASSERT_TRUE(clean(check_map(map.sphere, map.triangles)));
  // A vertex v of a triangle (v, a, b) pushed onto the great circle through a and b, then
  // back inside by a distance small enough that the float32 rounding breaks the triangle
  // while double still calls it valid. Which side the rounding errs to is fixed by the
  // points, so triangles are tried until one breaks.
  bool found = false;
  for (size_t k = 0; k < map.triangles.size() && !found; ++k) {
    const Triangle t = map.triangles[k];
    const uint32_t v = t[0];
    const Vec3 original = map.sphere[v], a = map.sphere[t[1]], b = map.sphere[t[2]];
    const Vec3 normal = normalized_or(cross(a, b), Vec3{});
    const Vec3 on_edge = normalized_or(a + b, a);
    for (double inside = 1e-11; inside < 1e-6 && !found; inside *= 1.5) {
      map.sphere[v] = normalized_or(on_edge + normal * inside, on_edge);
      found = clean(check_map(map.sphere, map.triangles)) &&
              !clean(check_map(rounded_to_float32(map.sphere), map.triangles));
    }
    if (!found) map.sphere[v] = original;
  }
  ASSERT_TRUE(found) << "no placement folds in float32 only";

  const size_t moved = rescue_float32(map.sphere, map.triangles);
  EXPECT_GT(moved, 0u);
  EXPECT_TRUE(clean(check_map(map.sphere, map.triangles)));
  EXPECT_TRUE(clean(check_map(rounded_to_float32(map.sphere), map.triangles)));
  for (const Vec3& p : map.sphere) EXPECT_NEAR(norm(p), 1.0, 1e-12);
}

TEST(Float32Rescue, AMapWithNothingFailingIsUnchanged) {
  Map map = identity_map();
  const std::vector<Vec3> before = map.sphere;
  EXPECT_EQ(rescue_float32(map.sphere, map.triangles), 0u);
  EXPECT_EQ(map.sphere, before);
}

}  // namespace
}  // namespace spheremap
