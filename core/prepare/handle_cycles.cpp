#include "core/prepare/handle_cycles.h"

#include <algorithm>
#include <bit>
#include <functional>
#include <limits>
#include <unordered_map>
#include <utility>

#include "core/mesh/union_find.h"
#include "core/prepare/hole_filling.h"

namespace spheremap {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

struct Edge {
  uint32_t u = 0, v = 0;                  // local vertices
  uint32_t face0 = kNone, face1 = kNone;  // local faces on its two sides
  double length = 0;
};

// An edge as seen from one of its ends: the shortest-path searches read only these rows
// (the far end and length beside the edge's id, not behind it: one scattered read fewer
// per arc relaxed).
struct Arc {
  uint32_t to = 0, edge = 0;
  double length = 0;
};

// The part's vertices, edges and vertex-edge adjacency (compressed rows), in local ids.
struct PartGraph {
  std::vector<uint32_t> vertex;  // local -> mesh vertex
  std::vector<Edge> edges;
  std::vector<uint32_t> first;  // arcs of local vertex a: arcs[first[a]..first[a+1])
  std::vector<Arc> arcs;
};

// Edges seen while scanning faces, by their ends' local ids: each edge kept in the row of its
// smaller end (a few entries, scanned), past kScanned entries in a hash map (a fan's centre
// of thousands of faces: no quadratic scan). Flat arrays for the common case: the graph is
// made again after every handle cut (a cave of 593K faces: 0.9 s per cut with a hash map of
// every edge).
class EdgeIds {
 public:
  // `corners`: per local vertex, how many corners it has (it has at most twice as many
  // edges; its row holds up to kScanned of them).
  explicit EdgeIds(const std::vector<uint32_t>& corners)
      : start_(corners.size() + 1, 0), used_(corners.size(), 0) {
    for (size_t a = 0; a < corners.size(); ++a)
      start_[a + 1] = start_[a] + std::min(2 * corners[a], kScanned);
    row_.resize(start_.back());
  }
  // The id of edge {a, b} (local ids), or `next` when it is new (then recorded as that).
  uint32_t find_or_add(uint32_t a, uint32_t b, uint32_t next) {
    const uint32_t low = std::min(a, b), high = std::max(a, b);
    const auto row = row_.begin() + start_[low], end = row + used_[low];
    const auto it = std::find_if(row, end, [&](const auto& entry) { return entry.first == high; });
    if (it != end) return it->second;
    if (used_[low] < start_[low + 1] - start_[low]) {
      *end = {high, next};
      ++used_[low];
      return next;
    }
    return crowded_.try_emplace(uint64_t{low} << 32 | high, next).first->second;
  }

 private:
  static constexpr uint32_t kScanned = 32;
  std::vector<uint32_t> start_, used_;
  std::vector<std::pair<uint32_t, uint32_t>> row_;  // (larger end, edge id)
  std::unordered_map<uint64_t, uint32_t> crowded_;
};

PartGraph part_graph(const PolygonMesh& mesh, std::span<const uint32_t> faces) {
  PartGraph g;
  // Local ids in the order of the vertices' first corners (the order in which the edges,
  // made in face order, first reach them).
  std::vector<uint32_t> local(mesh.vertex_count(), kNone), corners;
  for (uint32_t f : faces)
    for (uint32_t v : mesh.face(f)) {
      if (local[v] == kNone) {
        local[v] = static_cast<uint32_t>(g.vertex.size());
        g.vertex.push_back(v);
        corners.push_back(0);
      }
      ++corners[local[v]];
    }
  EdgeIds edge_ids(corners);
  for (size_t lf = 0; lf < faces.size(); ++lf) {
    const auto face = mesh.face(faces[lf]);
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      const auto next = static_cast<uint32_t>(g.edges.size());
      const uint32_t id = edge_ids.find_or_add(local[a], local[b], next);
      if (id == next) {
        Edge e;
        e.u = local[a];
        e.v = local[b];
        e.face0 = static_cast<uint32_t>(lf);
        e.length = norm(mesh.positions[b] - mesh.positions[a]);
        g.edges.push_back(e);
      } else {
        g.edges[id].face1 = static_cast<uint32_t>(lf);
      }
    }
  }
  g.first.assign(g.vertex.size() + 1, 0);
  for (const Edge& e : g.edges) ++g.first[e.u + 1], ++g.first[e.v + 1];
  for (size_t a = 0; a < g.vertex.size(); ++a) g.first[a + 1] += g.first[a];
  g.arcs.resize(g.first.back());
  std::vector<uint32_t> fill(g.first.begin(), g.first.end() - 1);
  for (uint32_t e = 0; e < g.edges.size(); ++e) {
    const Edge& edge = g.edges[e];
    g.arcs[fill[edge.u]++] = {edge.v, e, edge.length};
    g.arcs[fill[edge.v]++] = {edge.u, e, edge.length};
  }
  return g;
}

// A shortest-path tree: per vertex its distance, tree edge (kNone at the root) and depth.
struct PathTree {
  std::vector<double> distance;
  std::vector<uint32_t> parent_edge, depth;
};

// A 4-ary min-heap of (distance, vertex): pops in the order std::priority_queue with
// std::greater pops (the least pair first), with half the levels of a binary heap.
class DistanceHeap {
 public:
  using Item = std::pair<double, uint32_t>;
  bool empty() const { return items_.empty(); }
  void push(Item item) {
    size_t at = items_.size();
    items_.push_back(item);
    while (at > 0) {
      const size_t parent = (at - 1) / 4;
      if (!(item < items_[parent])) break;
      items_[at] = items_[parent];
      at = parent;
    }
    items_[at] = item;
  }
  Item pop() {
    const Item top = items_.front();
    const Item last = items_.back();
    items_.pop_back();
    const size_t n = items_.size();
    if (n == 0) return top;
    size_t at = 0;
    for (;;) {
      const size_t child = 4 * at + 1;
      if (child >= n) break;
      size_t least = child;
      for (size_t c = child + 1; c < std::min(child + 4, n); ++c)
        if (items_[c] < items_[least]) least = c;
      if (!(items_[least] < last)) break;
      items_[at] = items_[least];
      at = least;
    }
    items_[at] = last;
    return top;
  }

 private:
  std::vector<Item> items_;
};

PathTree shortest_path_tree(const PartGraph& g, uint32_t root, const StopCheck* stop) {
  PathTree t;
  const size_t n = g.vertex.size();
  t.distance.assign(n, std::numeric_limits<double>::infinity());
  t.parent_edge.assign(n, kNone);
  t.depth.assign(n, 0);
  std::vector<char> done(n, 0);
  std::vector<uint32_t> parent(n, kNone);
  DistanceHeap queue;
  t.distance[root] = 0;
  queue.push({0, root});
  size_t popped = 0;
  while (!queue.empty()) {
    const auto [d, a] = queue.pop();
    if (done[a]) continue;
    done[a] = 1;
    if (stop && ++popped % StopCheck::kInterval == 0) stop->check();
    if (parent[a] != kNone) t.depth[a] = t.depth[parent[a]] + 1;
    for (uint32_t k = g.first[a]; k < g.first[a + 1]; ++k) {
      const Arc& arc = g.arcs[k];
      if (done[arc.to] || !(d + arc.length < t.distance[arc.to])) continue;
      t.distance[arc.to] = d + arc.length;
      t.parent_edge[arc.to] = arc.edge;
      parent[arc.to] = a;
      queue.push({t.distance[arc.to], arc.to});
    }
  }
  return t;
}

uint32_t tree_parent(const PartGraph& g, const PathTree& t, uint32_t a) {
  const Edge& e = g.edges[t.parent_edge[a]];
  return e.u == a ? e.v : e.u;
}

// The simple cycle of non-tree edge e: from e.u up to where the tree paths of u and v
// meet, then down to e.v (e joins it back to e.u).
HandleCycle cycle_of(const PartGraph& g, const PathTree& t, const Edge& e) {
  std::vector<uint32_t> up_u, up_v;
  uint32_t a = e.u, b = e.v;
  while (t.depth[a] > t.depth[b]) up_u.push_back(a), a = tree_parent(g, t, a);
  while (t.depth[b] > t.depth[a]) up_v.push_back(b), b = tree_parent(g, t, b);
  while (a != b) {
    up_u.push_back(a), a = tree_parent(g, t, a);
    up_v.push_back(b), b = tree_parent(g, t, b);
  }
  HandleCycle cycle;
  for (uint32_t v : up_u) cycle.vertices.push_back(g.vertex[v]);
  cycle.vertices.push_back(g.vertex[a]);
  for (auto it = up_v.rbegin(); it != up_v.rend(); ++it) cycle.vertices.push_back(g.vertex[*it]);
  cycle.length = t.distance[e.u] + t.distance[e.v] - 2 * t.distance[a] + e.length;
  return cycle;
}

// Sorts (length, edge) pairs listed by increasing edge into increasing (length, edge): a
// stable radix sort on the lengths' bits (non-negative doubles order as their bits do),
// skipping the digits every length shares. std::sort of the pairs was a quarter of a
// many-handled part's closing (carbon-sphere.glb: 91 handles, 211K faces).
void sort_by_length(std::vector<std::pair<double, uint32_t>>& items) {
  constexpr int kBits = 11;
  constexpr size_t kBuckets = size_t{1} << kBits;
  std::vector<std::pair<double, uint32_t>> other(items.size());
  std::vector<size_t> count(kBuckets);
  for (int shift = 0; shift < 64; shift += kBits) {
    auto digit = [shift](double length) {
      return static_cast<size_t>((std::bit_cast<uint64_t>(length) >> shift) & (kBuckets - 1));
    };
    std::fill(count.begin(), count.end(), 0);
    for (const auto& item : items) ++count[digit(item.first)];
    if (std::count(count.begin(), count.end(), items.size())) continue;  // one digit for all
    size_t sum = 0;
    for (size_t& c : count) sum += std::exchange(c, sum);
    for (const auto& item : items) other[count[digit(item.first)]++] = item;
    items.swap(other);
  }
}

// The leftover edges' cycles of the tree-cotree basis rooted at `root`.
void basis_cycles(const PartGraph& g, const PathTree& t, size_t face_count,
                  std::vector<HandleCycle>& out) {
  std::vector<char> in_tree(g.edges.size(), 0);
  for (uint32_t e : t.parent_edge)
    if (e != kNone) in_tree[e] = 1;
  std::vector<std::pair<double, uint32_t>> others;  // (loop length, edge), by edge
  for (uint32_t e = 0; e < g.edges.size(); ++e)
    if (!in_tree[e])
      others.push_back(
          {t.distance[g.edges[e].u] + t.distance[g.edges[e].v] + g.edges[e].length, e});
  // The dual tree takes the longest loops first (the later edge first among equal ones), so
  // what is left is the shortest: ascending by (length, edge), read from the back.
  sort_by_length(others);
  UnionFind dual(face_count);
  for (auto it = others.rbegin(); it != others.rend(); ++it) {
    const uint32_t e = it->second;
    const Edge& edge = g.edges[e];
    if (edge.face0 == kNone || edge.face1 == kNone) continue;
    if (dual.find(edge.face0) != dual.find(edge.face1)) {
      dual.unite(edge.face0, edge.face1);
      continue;
    }
    out.push_back(cycle_of(g, t, edge));
  }
}

}  // namespace

std::vector<HandleCycle> handle_cycles(const PolygonMesh& mesh, std::span<const uint32_t> faces,
                                       size_t roots, const StopCheck* stop) {
  std::vector<HandleCycle> cycles;
  if (faces.empty()) return cycles;
  const PartGraph g = part_graph(mesh, faces);
  uint32_t root = 0;
  for (size_t r = 0; r < roots; ++r) {
    if (stop) stop->check();
    const PathTree t = shortest_path_tree(g, root, stop);
    basis_cycles(g, t, faces.size(), cycles);
    // The next root: the vertex farthest from this one (another side of the part).
    root = static_cast<uint32_t>(std::max_element(t.distance.begin(), t.distance.end()) -
                                 t.distance.begin());
  }
  std::stable_sort(cycles.begin(), cycles.end(),
                   [](const HandleCycle& a, const HandleCycle& b) { return a.length < b.length; });
  return cycles;
}

}  // namespace spheremap
