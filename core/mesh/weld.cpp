#include "core/mesh/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <tuple>

#include "core/mesh/input_error.h"
#include "core/mesh/union_find.h"

namespace spheremap {
namespace {

// Union of exactly equal finite positions: sort indices by position.
void unite_equal(const std::vector<Vec3>& p, UnionFind& sets) {
  std::vector<uint32_t> order;
  order.reserve(p.size());
  for (uint32_t i = 0; i < p.size(); ++i)
    if (is_finite(p[i])) order.push_back(i);
  auto key = [&](uint32_t i) { return std::tie(p[i].x, p[i].y, p[i].z); };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  for (size_t k = 1; k < order.size(); ++k)
    if (p[order[k]] == p[order[k - 1]]) sets.unite(order[k], order[k - 1]);
}

// Union of finite positions within `radius`. A uniform grid of cell size radius / sqrt(3),
// so every two points of one cell are within radius and a cell is united in one pass;
// then each cell is compared with the cells up to two steps away, stopping at the first
// pair within radius and skipping cells already in one set. A large tolerance no longer
// compares every pair (measured: weld_tolerance = 1 was O(n^2) on the HTTP thread); the
// comparisons are still capped, with an error that names the option.
//
// The cells are the points sorted by cell, found by an open-addressing table of cell
// starts: 62 lookups per cell, nearly all of empty cells. A std::unordered_map of cells
// spent them walking bucket chains: 12% of a 178K-face room's whole map, whose weld trials
// run it five times. The sets formed do not depend on the order cells are visited in.
void unite_within(const std::vector<Vec3>& p, double radius, UnionFind& sets, StopCheck& stop) {
  using Key = std::array<int64_t, 3>;
  // Spelled out: std::array's == and < on int64_t became a call to memcmp per comparison,
  // a fifth of the preparation of a 1.3M-triangle asset (its weld trials weld it at 1e-4).
  auto same = [](const Key& a, const Key& b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; };
  auto before = [](const Key& a, const Key& b) {
    if (a[0] != b[0]) return a[0] < b[0];
    return a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
  };
  const double cell = radius / std::sqrt(3.0);
  auto cell_of = [&](const Vec3& q) {
    return Key{static_cast<int64_t>(std::floor(q.x / cell)),
               static_cast<int64_t>(std::floor(q.y / cell)),
               static_cast<int64_t>(std::floor(q.z / cell))};
  };
  std::vector<std::pair<Key, uint32_t>> points;
  points.reserve(p.size());
  for (uint32_t i = 0; i < p.size(); ++i) {
    stop.tick();
    if (is_finite(p[i])) points.push_back({cell_of(p[i]), i});
  }
  std::sort(points.begin(), points.end(), [&](const auto& a, const auto& b) {
    return same(a.first, b.first) ? a.second < b.second : before(a.first, b.first);
  });
  stop.check();
  std::vector<uint32_t> starts;  // cell c is points[starts[c], starts[c + 1])
  for (uint32_t k = 0; k < points.size(); ++k)
    if (k == 0 || !same(points[k].first, points[k - 1].first)) starts.push_back(k);
  const size_t cells = starts.size();
  starts.push_back(static_cast<uint32_t>(points.size()));
  auto hash = [](const Key& c) {  // multiply-xorshift rounds over the three coordinates
    uint64_t h = 0;
    for (int64_t v : c) {
      h = (h ^ static_cast<uint64_t>(v)) * 0x9e3779b97f4a7c15ull;
      h ^= h >> 31;
    }
    return h * 0xbf58476d1ce4e5b9ull;
  };
  size_t slots = 1;
  while (slots < 2 * cells) slots *= 2;
  std::vector<uint32_t> table(slots, UINT32_MAX);  // cell ids, linear probing
  for (uint32_t c = 0; c < cells; ++c) {
    size_t s = hash(points[starts[c]].first) & (slots - 1);
    while (table[s] != UINT32_MAX) s = (s + 1) & (slots - 1);
    table[s] = c;
  }
  auto find_cell = [&](const Key& key) -> uint32_t {
    for (size_t s = hash(key) & (slots - 1);; s = (s + 1) & (slots - 1))
      if (table[s] == UINT32_MAX || same(points[starts[table[s]]].first, key)) return table[s];
  };
  for (uint32_t c = 0; c < cells; ++c)
    for (uint32_t k = starts[c] + 1; k < starts[c + 1]; ++k)
      sets.unite(points[starts[c]].second, points[k].second);
  const double r2 = radius * radius;
  const uint64_t budget = 200'000'000;  // pair distance tests, ~1 s
  uint64_t tests = 0;
  for (uint32_t c = 0; c < cells; ++c) {
    stop.tick();
    const Key& key = points[starts[c]].first;
    const uint32_t first = points[starts[c]].second;
    for (int64_t dx = -2; dx <= 2; ++dx)
      for (int64_t dy = -2; dy <= 2; ++dy)
        for (int64_t dz = -2; dz <= 2; ++dz) {
          const Key other_key{key[0] + dx, key[1] + dy, key[2] + dz};
          if (!before(other_key, key)) continue;  // each pair of cells once
          const uint32_t other = find_cell(other_key);
          if (other == UINT32_MAX) continue;
          if (sets.find(first) == sets.find(points[starts[other]].second)) continue;
          bool joined = false;
          for (uint32_t a = starts[c]; a < starts[c + 1] && !joined; ++a)
            for (uint32_t b = starts[other]; b < starts[other + 1]; ++b)
              if (++tests, stop.tick(),
                  squared_norm(p[points[a].second] - p[points[b].second]) <= r2) {
                joined = true;
                break;
              }
          if (joined) sets.unite(first, points[starts[other]].second);
          if (tests > budget)
            throw InputError("weld", "weld tolerance " + std::to_string(radius) +
                                         " compares too many vertex pairs (over " +
                                         std::to_string(budget) +
                                         "); use a smaller weld_tolerance");
        }
  }
}

double bounding_box_diagonal(const std::vector<Vec3>& p) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& q : p) {
    if (!is_finite(q)) continue;
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
  return lo.x <= hi.x ? norm(hi - lo) : 0.0;
}

}  // namespace

WeldResult weld(const PolygonMesh& input, double relative_tolerance, StopCheck* stop) {
  StopCheck never(nullptr);
  StopCheck& check = stop ? *stop : never;
  const size_t n = input.vertex_count();
  UnionFind sets(n);
  check.check();
  unite_equal(input.positions, sets);
  check.check();  // the sort is not ticked: asked before and after it (~1 s at the caps)
  const double radius = relative_tolerance * bounding_box_diagonal(input.positions);
  if (radius > 0) unite_within(input.positions, radius, sets, check);

  std::vector<char> referenced(n, 0);
  for (uint32_t v : input.indices) referenced[v] = 1;

  // Each group is named by its first referenced member; new ids follow that order.
  WeldResult result;
  result.input_to_welded.assign(n, kUnreferenced);
  // At most n positions: reserved, not grown by doubling (up to twice the mesh's
  // positions, held through the whole map: 11 bytes per triangle at 17M triangles).
  result.mesh.positions.reserve(n);
  std::vector<uint32_t> group_id(n, kUnreferenced);
  for (uint32_t i = 0; i < n; ++i) {
    if (!referenced[i]) {
      ++result.unreferenced_vertices;
      continue;
    }
    uint32_t root = sets.find(i);
    if (group_id[root] == kUnreferenced) {
      group_id[root] = static_cast<uint32_t>(result.mesh.positions.size());
      result.mesh.positions.push_back(input.positions[i]);
    }
    result.input_to_welded[i] = group_id[root];
  }
  if (result.mesh.positions.capacity() > result.mesh.positions.size() + n / 4)
    result.mesh.positions.shrink_to_fit();  // many welded away (seams): give the rest back
  // An unreferenced vertex at the position of a referenced one still has a sphere point.
  for (uint32_t i = 0; i < n; ++i)
    if (!referenced[i]) result.input_to_welded[i] = group_id[sets.find(i)];

  result.mesh.offsets = input.offsets;
  result.mesh.indices.resize(input.indices.size());
  for (size_t k = 0; k < input.indices.size(); ++k)
    result.mesh.indices[k] = result.input_to_welded[input.indices[k]];
  return result;
}

size_t drop_unused_vertices(WeldResult& welded) {
  PolygonMesh& mesh = welded.mesh;
  std::vector<uint32_t> renamed(mesh.vertex_count(), kUnreferenced);
  for (uint32_t v : mesh.indices) renamed[v] = 0;
  uint32_t next = 0;
  for (size_t v = 0; v < renamed.size(); ++v)
    if (renamed[v] == 0) {
      mesh.positions[next] = mesh.positions[v];
      renamed[v] = next++;
    }
  const size_t dropped = mesh.vertex_count() - next;
  if (dropped == 0) return 0;
  mesh.positions.resize(next);
  for (uint32_t& v : mesh.indices) v = renamed[v];
  for (uint32_t& v : welded.input_to_welded)
    if (v != kUnreferenced) v = renamed[v];
  return dropped;
}

}  // namespace spheremap
