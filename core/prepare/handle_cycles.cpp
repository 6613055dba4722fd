#include "core/prepare/handle_cycles.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

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

// The part's vertices, edges and vertex-edge adjacency (compressed rows), in local ids.
struct PartGraph {
  std::vector<uint32_t> vertex;  // local -> mesh vertex
  std::vector<Edge> edges;
  std::vector<uint32_t> first, incident;  // edges of local vertex a: incident[first[a]..first[a+1])
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
  g.incident.resize(g.first.back());
  std::vector<uint32_t> fill(g.first.begin(), g.first.end() - 1);
  for (uint32_t e = 0; e < g.edges.size(); ++e) {
    g.incident[fill[g.edges[e].u]++] = e;
    g.incident[fill[g.edges[e].v]++] = e;
  }
  return g;
}

// A shortest-path tree: per vertex its distance, tree edge (kNone at the root) and depth.
struct PathTree {
  std::vector<double> distance;
  std::vector<uint32_t> parent_edge, depth;
};

PathTree shortest_path_tree(const PartGraph& g, uint32_t root, const StopCheck* stop) {
  PathTree t;
  const size_t n = g.vertex.size();
  t.distance.assign(n, std::numeric_limits<double>::infinity());
  t.parent_edge.assign(n, kNone);
  t.depth.assign(n, 0);
  std::vector<char> done(n, 0);
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  t.distance[root] = 0;
  queue.push({0, root});
  size_t popped = 0;
  while (!queue.empty()) {
    const auto [d, a] = queue.top();
    queue.pop();
    if (done[a]) continue;
    done[a] = 1;
    if (stop && ++popped % StopCheck::kInterval == 0) stop->check();
    if (t.parent_edge[a] != kNone) {
      const Edge& e = g.edges[t.parent_edge[a]];
      t.depth[a] = t.depth[e.u == a ? e.v : e.u] + 1;
    }
    for (uint32_t k = g.first[a]; k < g.first[a + 1]; ++k) {
      const Edge& e = g.edges[g.incident[k]];
      const uint32_t b = e.u == a ? e.v : e.u;
      if (done[b] || !(d + e.length < t.distance[b])) continue;
      t.distance[b] = d + e.length;
      t.parent_edge[b] = g.incident[k];
      queue.push({t.distance[b], b});
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

// The leftover edges' cycles of the tree-cotree basis rooted at `root`.
void basis_cycles(const PartGraph& g, const PathTree& t, size_t face_count,
                  std::vector<HandleCycle>& out) {
  std::vector<char> in_tree(g.edges.size(), 0);
  for (uint32_t e : t.parent_edge)
    if (e != kNone) in_tree[e] = 1;
  std::vector<std::pair<double, uint32_t>> others;  // (loop length, edge)
  for (uint32_t e = 0; e < g.edges.size(); ++e)
    if (!in_tree[e])
      others.push_back(
          {t.distance[g.edges[e].u] + t.distance[g.edges[e].v] + g.edges[e].length, e});
  // The dual tree takes the longest loops first, so what is left is the shortest.
  std::sort(others.begin(), others.end(), std::greater<>());
  UnionFind dual(face_count);
  for (const auto& [loop, e] : others) {
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
