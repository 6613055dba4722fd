#include "core/mesh/weld.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <tuple>

#include "core/mesh/input_error.h"
#include "core/mesh/triangle_tree.h"
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

// The box of the finite positions (lo > hi when there is none).
AxisBox finite_box(const std::vector<Vec3>& p) {
  AxisBox box;
  for (const Vec3& q : p)
    if (is_finite(q)) box.add(q);
  return box;
}

std::string shown(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// Union of finite positions within `radius`. A uniform grid of cell size radius / sqrt(3),
// so every two points of one cell are within radius and a cell is united in one pass;
// then each cell is compared with the cells up to two steps away, stopping at the first
// pair within radius and skipping cells already in one set. A large tolerance no longer
// compares every pair (measured: weld_tolerance = 1 was O(n^2) on the HTTP thread); the
// comparisons are still capped, with an error that names the option.
//
// The cells are the points sorted by cell (x, then y, then z), so a column of cells (one
// x and y) is a run sorted by z. Each column looks up its 12 neighbour columns before it
// (dx, dy within 2) in an open-addressing table of columns and walks each beside its own,
// cells within 2 in z; within a column, the 2 cells below. Looking up each of a cell's 62
// neighbour cells instead (nearly all empty) was most of the weld's time on a 1.3M-vertex
// asset, and a std::unordered_map of cells before that spent it walking bucket chains. The
// sets formed (connected components of "within radius") do not depend on the order.
// `box`: the finite positions' (finite_box).
void unite_within(const std::vector<Vec3>& p, const AxisBox& box, double radius, UnionFind& sets,
                  StopCheck& stop) {
  struct Cell {
    int64_t x, y, z;
  };
  const double cell = radius / std::sqrt(3.0);
  // Counted from the box's low corner, so an asset far from the origin has small cell
  // numbers; a radius so small that the box spans more cells than an int64_t counts is
  // refused rather than overflowed.
  const Vec3 &lo = box.lo, &hi = box.hi;
  const double widest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(widest / cell < 0x1p60))
    throw InputError("weld", "weld radius " + shown(radius) +
                                 " is too small for the mesh's extent (" + shown(widest) +
                                 "); use 0 (exact positions) or a larger weld_tolerance");
  auto cell_of = [&](const Vec3& q) {
    return Cell{static_cast<int64_t>(std::floor((q.x - lo.x) / cell)),
                static_cast<int64_t>(std::floor((q.y - lo.y) / cell)),
                static_cast<int64_t>(std::floor((q.z - lo.z) / cell))};
  };
  std::vector<std::pair<Cell, uint32_t>> points;
  points.reserve(p.size());
  for (uint32_t i = 0; i < p.size(); ++i) {
    stop.tick();
    if (is_finite(p[i])) points.push_back({cell_of(p[i]), i});
  }
  auto same_column = [](const Cell& a, const Cell& b) { return a.x == b.x && a.y == b.y; };
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    const Cell &u = a.first, &v = b.first;
    if (u.x != v.x) return u.x < v.x;
    if (u.y != v.y) return u.y < v.y;
    return u.z != v.z ? u.z < v.z : a.second < b.second;
  });
  stop.check();
  // Cell c is points[starts[c], starts[c + 1]); column k is cells [columns[k], columns[k + 1]).
  std::vector<uint32_t> starts, columns;
  for (uint32_t k = 0; k < points.size(); ++k) {
    const Cell& here = points[k].first;
    const bool new_column = k == 0 || !same_column(here, points[k - 1].first);
    if (new_column || here.z != points[k - 1].first.z) {
      if (new_column) columns.push_back(static_cast<uint32_t>(starts.size()));
      starts.push_back(k);
    }
  }
  const size_t cells = starts.size(), column_count = columns.size();
  starts.push_back(static_cast<uint32_t>(points.size()));
  columns.push_back(static_cast<uint32_t>(cells));
  auto cell_key = [&](uint32_t c) -> const Cell& { return points[starts[c]].first; };
  auto first_point = [&](uint32_t c) { return points[starts[c]].second; };
  auto hash = [](int64_t x, int64_t y) {  // multiply-xorshift rounds over two coordinates
    uint64_t h = 0;
    for (int64_t v : {x, y}) {
      h = (h ^ static_cast<uint64_t>(v)) * 0x9e3779b97f4a7c15ull;
      h ^= h >> 31;
    }
    return h * 0xbf58476d1ce4e5b9ull;
  };
  size_t slots = 1;
  while (slots < 2 * column_count) slots *= 2;
  std::vector<uint32_t> table(slots, UINT32_MAX);  // column ids, linear probing
  for (uint32_t k = 0; k < column_count; ++k) {
    const Cell& c = cell_key(columns[k]);
    size_t s = hash(c.x, c.y) & (slots - 1);
    while (table[s] != UINT32_MAX) s = (s + 1) & (slots - 1);
    table[s] = k;
  }
  auto find_column = [&](int64_t x, int64_t y) -> uint32_t {
    for (size_t s = hash(x, y) & (slots - 1);; s = (s + 1) & (slots - 1)) {
      if (table[s] == UINT32_MAX) return UINT32_MAX;
      const Cell& c = cell_key(columns[table[s]]);
      if (c.x == x && c.y == y) return table[s];
    }
  };
  for (uint32_t c = 0; c < cells; ++c)
    for (uint32_t k = starts[c] + 1; k < starts[c + 1]; ++k)
      sets.unite(first_point(c), points[k].second);
  const double r2 = radius * radius;
  const uint64_t budget = 200'000'000;  // pair distance tests, ~1 s
  uint64_t tests = 0;
  auto compare = [&](uint32_t c, uint32_t other) {
    if (sets.find(first_point(c)) == sets.find(first_point(other))) return;
    bool joined = false;
    for (uint32_t a = starts[c]; a < starts[c + 1] && !joined; ++a)
      for (uint32_t b = starts[other]; b < starts[other + 1]; ++b)
        if (++tests, stop.tick(), squared_norm(p[points[a].second] - p[points[b].second]) <= r2) {
          joined = true;
          break;
        }
    if (joined) sets.unite(first_point(c), first_point(other));
    if (tests > budget)
      throw InputError("weld", "weld tolerance " + std::to_string(radius) +
                                   " compares too many vertex pairs (over " +
                                   std::to_string(budget) + "); use a smaller weld_tolerance");
  };
  for (uint32_t k = 0; k < column_count; ++k) {
    const uint32_t begin = columns[k], end = columns[k + 1];
    stop.tick(end - begin);
    const Cell& column = cell_key(begin);
    // Within the column: each cell with the (at most 2) cells up to 2 below it.
    for (uint32_t c = begin; c < end; ++c)
      for (uint32_t o = c; o-- > begin && cell_key(c).z - cell_key(o).z <= 2;) compare(c, o);
    // The columns before it: dx < 0, or dx = 0 and dy < 0; their cells within 2 in z.
    for (int64_t dx = -2; dx <= 0; ++dx)
      for (int64_t dy = -2; dy <= 2 && !(dx == 0 && dy >= 0); ++dy) {
        const uint32_t other = find_column(column.x + dx, column.y + dy);
        if (other == UINT32_MAX) continue;
        const uint32_t other_end = columns[other + 1];
        uint32_t low = columns[other];  // the first of its cells not below z - 2
        for (uint32_t c = begin; c < end; ++c) {
          const int64_t z = cell_key(c).z;
          while (low < other_end && cell_key(low).z < z - 2) ++low;
          for (uint32_t o = low; o < other_end && cell_key(o).z <= z + 2; ++o) compare(c, o);
        }
      }
  }
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
  const AxisBox box = finite_box(input.positions);
  const double radius = relative_tolerance * (box.lo.x <= box.hi.x ? norm(box.hi - box.lo) : 0.0);
  if (radius > 0) unite_within(input.positions, box, radius, sets, check);

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
