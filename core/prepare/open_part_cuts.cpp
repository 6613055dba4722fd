#include "core/prepare/open_part_cuts.h"

#include <limits>
#include <optional>
#include <queue>
#include <vector>

#include "core/mesh/submesh.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/corner_map.h"
#include "core/prepare/hole_filling.h"    // directed_edge_key
#include "core/prepare/sheet_doubling.h"  // is_open_sphere

namespace spheremap {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// The half-edges of a manifold, consistently oriented part: a -> b to the slot of a's corner
// in the face running a -> b, and per vertex the slot of its boundary half-edge (the one
// a -> b with no b -> a; a manifold vertex has at most one), or kNone.
struct HalfEdges {
  CornerMap corner_at;
  std::vector<uint32_t> boundary_out;
  std::vector<uint32_t> boundary_next;  // per boundary vertex: the next one along its loop
};

// Nothing when the part is not consistently oriented and manifold at its edges.
std::optional<HalfEdges> half_edges(const PolygonMesh& mesh) {
  std::optional<CornerMap> corner_at = corner_map(mesh);
  if (!corner_at) return std::nullopt;
  HalfEdges h;
  h.corner_at = std::move(*corner_at);
  h.boundary_out.assign(mesh.vertex_count(), kNone);
  h.boundary_next.assign(mesh.vertex_count(), kNone);
  for (const auto& [key, slot] : h.corner_at) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    if (h.corner_at.count(directed_edge_key(b, a))) continue;
    h.boundary_out[a] = slot;
    h.boundary_next[a] = b;
  }
  return h;
}

// The shortest path along edges from the loop through `start` (a boundary vertex) to a
// boundary vertex of another loop, from there back to the loop (path[0] on it). Its inner
// vertices are inner vertices of the part: the first other loop's vertex reached ends it.
// Empty when no other loop is reached.
std::vector<uint32_t> path_to_another_loop(const PolygonMesh& mesh, const HalfEdges& h,
                                           uint32_t start, const StopCheck* stop) {
  const size_t n = mesh.vertex_count();
  std::vector<char> on_start_loop(n, 0);
  uint32_t v = start;
  do {
    on_start_loop[v] = 1;
    v = h.boundary_next[v];
  } while (v != start && v != kNone && !on_start_loop[v]);
  // Each vertex's neighbours, from the half-edges (each undirected edge both ways).
  std::vector<std::vector<uint32_t>> neighbours(n);
  for (const auto& [key, slot] : h.corner_at) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    neighbours[a].push_back(b);
    if (h.boundary_next[a] == b) neighbours[b].push_back(a);  // no b -> a to add it
  }
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<uint32_t> parent(n, kNone);
  using Entry = std::pair<double, uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (uint32_t s = 0; s < n; ++s)
    if (on_start_loop[s]) distance[s] = 0, queue.push({0.0, s});
  size_t popped = 0;
  while (!queue.empty()) {
    const auto [d, a] = queue.top();
    queue.pop();
    if (d > distance[a]) continue;
    if (stop && ++popped % 4096 == 0) stop->check();
    if (h.boundary_out[a] != kNone && !on_start_loop[a]) {
      std::vector<uint32_t> path;
      for (uint32_t p = a; p != kNone; p = parent[p]) path.push_back(p);
      return {path.rbegin(), path.rend()};
    }
    for (uint32_t b : neighbours[a]) {
      const double through = d + norm(mesh.positions[b] - mesh.positions[a]);
      if (through < distance[b]) distance[b] = through, parent[b] = a, queue.push({through, b});
    }
  }
  return {};
}

// Cuts the part along `path` (from one loop to another): each path vertex gets a copy for
// its corners on the path's left, the faces from the one running v -> next round (in the
// order the faces around v follow: the one running v -> a, then the one running v -> the
// corner before a) to the one running prev -> v; an end's run starts or stops at the loop.
// Returns false (the mesh unchanged) when the faces around a path vertex do not run so.
bool cut_along(PolygonMesh& mesh, const HalfEdges& h, const std::vector<uint32_t>& path) {
  const size_t k = path.size();
  std::vector<std::vector<uint32_t>> left(k);  // per path vertex: its corners to rename
  for (size_t i = 0; i < k; ++i) {
    const uint32_t v = path[i];
    const uint32_t prev = i > 0 ? path[i - 1] : kNone, next = i + 1 < k ? path[i + 1] : kNone;
    uint32_t slot = h.boundary_out[v];
    if (next != kNone) {
      const auto it = h.corner_at.find(directed_edge_key(v, next));
      if (it == h.corner_at.end()) return false;
      slot = it->second;
    }
    if (slot == kNone) return false;
    for (size_t steps = 0;; ++steps) {
      if (steps > mesh.face_count()) return false;
      left[i].push_back(slot);
      const uint32_t a = vertex_before(mesh, slot);
      if (a == prev) break;
      const auto it = h.corner_at.find(directed_edge_key(v, a));
      if (it == h.corner_at.end()) {  // the loop: where the start's run ends
        if (prev == kNone) break;
        return false;
      }
      slot = it->second;
    }
  }
  for (size_t i = 0; i < k; ++i) {
    const uint32_t copy = static_cast<uint32_t>(mesh.positions.size());
    const Vec3 position = mesh.positions[path[i]];
    mesh.positions.push_back(position);
    for (uint32_t slot : left[i]) mesh.indices[slot] = copy;
  }
  return true;
}

// Cuts an open sphere of `loops` boundary loops (a part's own mesh) into a disc; false
// (and `part` as it may be half cut: the caller drops it) when a step fails.
bool cut_into_disc(PolygonMesh& part, size_t loops, size_t& paths, const StopCheck* stop) {
  for (; loops > 1; --loops) {
    const std::optional<HalfEdges> edges = half_edges(part);
    if (!edges) return false;
    const HalfEdges& h = *edges;
    uint32_t start = kNone;
    for (uint32_t v = 0; v < part.vertex_count() && start == kNone; ++v)
      if (h.boundary_out[v] != kNone) start = v;
    if (start == kNone) return false;
    const std::vector<uint32_t> path = path_to_another_loop(part, h, start, stop);
    if (path.size() < 2 || !cut_along(part, h, path)) return false;
    ++paths;
  }
  const TopologyReport cut = analyze_topology(part, stop);
  return is_open_sphere(cut) && cut.boundary_loops == 1;
}

}  // namespace

bool can_become_disc(const TopologyReport& topology, size_t corners) {
  return is_open_sphere(topology) && topology.boundary_loops <= kMaxJoinedLoops &&
         (topology.boundary_loops - 1) * corners <= kMaxCutWork;
}

OpenPartCuts cut_open_parts_into_discs(PolygonMesh& mesh, const StopCheck* stop) {
  OpenPartCuts result;
  std::vector<uint32_t> scratch(mesh.vertex_count(), kUnreferenced);
  for (const std::vector<uint32_t>& faces : connected_part_faces(mesh, stop)) {
    MeshPart part = submesh(mesh, faces, &scratch);
    const TopologyReport topology = analyze_topology(part.mesh, stop);
    if (topology.boundary_loops < 2 || !can_become_disc(topology, part.mesh.indices.size()))
      continue;
    const size_t n = part.vertex.size();
    size_t paths = 0;
    if (!cut_into_disc(part.mesh, topology.boundary_loops, paths, stop)) continue;
    // Back into the whole: the part's faces, in order, over its vertices and the copies
    // appended after the whole's.
    const uint32_t first_copy = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), part.mesh.positions.begin() + n,
                          part.mesh.positions.end());
    for (size_t k = 0; k < faces.size(); ++k) {
      const uint32_t whole = mesh.offsets[faces[k]], own = part.mesh.offsets[k];
      for (uint32_t c = 0; c < part.mesh.face_size(k); ++c) {
        const uint32_t v = part.mesh.indices[own + c];
        mesh.indices[whole + c] = v < n ? part.vertex[v] : first_copy + (v - n);
      }
    }
    ++result.parts_cut;
    result.paths_cut += paths;
    result.vertices_added += part.mesh.positions.size() - n;
  }
  return result;
}

}  // namespace spheremap
