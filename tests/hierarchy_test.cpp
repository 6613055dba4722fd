#include "core/map/hierarchy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>

#include "core/map/incidence_lists.h"
#include "core/map/partial_level.h"
#include "core/map/spherical_map.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

std::vector<uint32_t> as_vector(std::span<const uint32_t> list) {
  return {list.begin(), list.end()};
}

// The hierarchy breaks ties by list order: moving a list that outgrew its slice, and
// erasing from it, must keep the order a vector would have.
TEST(IncidenceLists, KeepTheirOrderThroughMovesAndErases) {
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  IncidenceLists lists(4, triangles);
  EXPECT_EQ(as_vector(lists[0]), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(as_vector(lists[3]), (std::vector<uint32_t>{1, 2, 3}));
  std::vector<uint32_t> expected = {0, 1, 2};
  for (uint32_t t = 10; t < 60; ++t) {  // far past the slack: moves the list several times
    lists.append(0, t);
    expected.push_back(t);
  }
  lists.erase(0, 1);
  lists.erase(0, 33);
  lists.erase(0, 99);  // not there: nothing changes
  std::erase(expected, 1u);
  std::erase(expected, 33u);
  EXPECT_EQ(as_vector(lists[0]), expected);
  // The other lists were not disturbed by the moves.
  EXPECT_EQ(as_vector(lists[1]), (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(as_vector(lists[3]), (std::vector<uint32_t>{1, 2, 3}));
  lists.clear(2);
  EXPECT_TRUE(lists.empty(2));
  lists.append(2, 7);
  EXPECT_EQ(as_vector(lists[2]), (std::vector<uint32_t>{7}));
}

// As the hierarchy uses them: collapse targets grow (their lists move again and again),
// collapsed vertices are cleared. The lists stay what vectors would hold, and the array
// stays within a small multiple of what the lists hold: compacted, not grown without bound
// by the slices that moved and cleared lists leave behind.
TEST(IncidenceLists, StayCompactThroughManyMovesAndClears) {
  constexpr uint32_t kVertices = 2000, kTargets = 16;
  std::vector<Triangle> triangles;
  for (uint32_t t = 0; t < kVertices; ++t)
    triangles.push_back({t, (t + 1) % kVertices, (t + 7) % kVertices});
  IncidenceLists lists(kVertices, triangles);
  std::vector<std::vector<uint32_t>> expected(kVertices);
  for (uint32_t t = 0; t < kVertices; ++t)
    for (uint32_t v : triangles[t]) expected[v].push_back(t);
  std::vector<uint32_t> alive(kVertices);
  std::iota(alive.begin(), alive.end(), 0u);
  uint64_t state = 12345;
  auto random = [&](size_t below) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<size_t>((state >> 33) % below);
  };
  uint32_t next_triangle = kVertices;
  while (alive.size() > kTargets) {
    for (int k = 0; k < 50; ++k) {  // appends to the first few vertices: their lists move
      const uint32_t v = alive[random(kTargets)];
      lists.append(v, next_triangle);
      expected[v].push_back(next_triangle++);
    }
    const uint32_t v = alive[random(alive.size())];
    if (!expected[v].empty()) {
      const uint32_t gone = expected[v][random(expected[v].size())];
      lists.erase(v, gone);
      expected[v].erase(std::find(expected[v].begin(), expected[v].end(), gone));
    }
    // A collapse: a vertex other than the targets has its list cleared for good.
    const size_t victim = kTargets + random(alive.size() - kTargets);
    lists.clear(alive[victim]);
    expected[alive[victim]].clear();
    alive.erase(alive.begin() + static_cast<std::ptrdiff_t>(victim));
    size_t held = 0;
    for (uint32_t w : alive) held += expected[w].size() + 4;
    ASSERT_LE(lists.slot_count(), 3 * held) << alive.size() << " lists alive";
  }
  for (uint32_t v = 0; v < kVertices; ++v) ASSERT_EQ(as_vector(lists[v]), expected[v]) << v;
}

// One vertex gaining 100,000 triangles in a small mesh (a fan collapsing onto its hub):
// the array is compacted a few times (each compaction keeps half as much room again in
// the growing list), not every few appends.
TEST(IncidenceLists, AGrowingFanCompactsRarely) {
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  IncidenceLists lists(4, triangles);
  std::vector<uint32_t> expected = {0, 1, 2};
  for (uint32_t t = 4; t < 100'004; ++t) {
    lists.append(0, t);
    expected.push_back(t);
  }
  EXPECT_EQ(as_vector(lists[0]), expected);
  EXPECT_EQ(as_vector(lists[3]), (std::vector<uint32_t>{1, 2, 3}));
  EXPECT_LE(lists.compaction_count(), 40u);
  EXPECT_LE(lists.slot_count(), 4 * expected.size());
}

// Every level of the hierarchy is a closed, oriented genus-0 triangle mesh on a prefix of
// the new ids, and every collapse record names a target in its ring of older vertices.
void expect_valid_hierarchy(const PolygonMesh& input) {
  const std::vector<Triangle> triangles = oriented_triangles(input).triangles;
  const CollapseHierarchy h = build_hierarchy(input.positions, triangles);
  const size_t n = input.vertex_count();
  ASSERT_EQ(h.new_to_old.size(), n);
  for (uint32_t id = 0; id < n; ++id) ASSERT_EQ(h.old_to_new[h.new_to_old[id]], id);
  ASSERT_EQ(h.level_sizes.front(), 4u);
  ASSERT_EQ(h.level_sizes.back(), n);
  ASSERT_TRUE(std::is_sorted(h.level_sizes.begin(), h.level_sizes.end()));
  ASSERT_EQ(h.level_triangles.size() + 1, h.level_sizes.size());
  for (size_t l = 0; l < h.level_triangles.size(); ++l) {
    const uint32_t size = h.level_sizes[l];
    const std::vector<Triangle>& level = h.level_triangles[l];
    EXPECT_EQ(level.size(), 2 * size_t{size} - 4) << "level " << l;  // Euler: F = 2V - 4
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const Triangle& t : level)
      for (int k = 0; k < 3; ++k) {
        ASSERT_LT(t[k], size) << "level " << l;
        ++directed[{t[k], t[(k + 1) % 3]}];
      }
    for (const auto& [edge, count] : directed) {
      EXPECT_EQ(count, 1) << "level " << l << ": edge used twice in one direction";
      EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "level " << l << ": open edge";
    }
  }
  for (uint32_t u = 4; u < n; ++u) {
    const std::span<const uint32_t> ring = h.ring(u);
    ASSERT_GE(ring.size(), 3u);
    EXPECT_NE(std::find(ring.begin(), ring.end(), h.collapse_target[u]), ring.end()) << u;
    for (uint32_t w : ring) EXPECT_LT(w, u) << "a ring vertex removed before " << u;
  }
}

TEST(Hierarchy, EveryLevelIsAClosedSphereOnAPrefixOfIds) {
  const std::vector<Vec3> limbs = {{1, 0, 0}, {0, 1, 0}, {-1, -1, 0}};
  expect_valid_hierarchy(testing::with_limbs(testing::icosphere(3), limbs, 2, 0.15));
  expect_valid_hierarchy(testing::quad_sphere(8));
}

// A 64-gon cap fanned from a centre: valences of 64 and more grow far past the lists'
// first slices, through the moves of IncidenceLists.
TEST(Hierarchy, HighValenceFansStayValid) {
  std::vector<std::array<double, 2>> star;
  for (int k = 0; k < 64; ++k) {
    const double angle = 2 * std::numbers::pi * k / 64, radius = k % 2 ? 0.4 : 1.0;
    star.push_back({radius * std::cos(angle), radius * std::sin(angle)});
  }
  expect_valid_hierarchy(testing::prism(star, 0.5, true));
}

// Inserting a level's vertices one by one into the coarser level's triangles gives the
// level's own triangles (each rotated to its smallest vertex), the finest level included.
void expect_partial_levels_rebuild_the_hierarchy(const PolygonMesh& input) {
  const std::vector<Triangle> triangles = oriented_triangles(input).triangles;
  const CollapseHierarchy h = build_hierarchy(input.positions, triangles, 2.0);
  auto rotated = [](std::vector<Triangle> list) {
    for (Triangle& t : list) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    std::sort(list.begin(), list.end());
    return list;
  };
  std::vector<Triangle> finest = triangles;
  for (Triangle& t : finest)
    for (uint32_t& v : t) v = h.old_to_new[v];
  for (size_t l = 1; l < h.level_sizes.size(); ++l) {
    PartialLevel partial(h.level_triangles[l - 1]);
    for (uint32_t u = h.level_sizes[l - 1]; u < h.level_sizes[l]; ++u)
      partial.split(u, h.collapse_target[u], h.ring(u));
    const std::vector<Triangle> built(partial.triangles().begin(), partial.triangles().end());
    EXPECT_EQ(rotated(built), rotated(l < h.level_triangles.size() ? h.level_triangles[l] : finest))
        << "level " << l;
  }
}

TEST(PartialLevel, InsertionsRebuildEveryLevel) {
  expect_partial_levels_rebuild_the_hierarchy(testing::icosphere(3));
  expect_partial_levels_rebuild_the_hierarchy(testing::capped_tube(8, 40, 20));
}

}  // namespace
}  // namespace spheremap
