#include "core/prepare/hole_filling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/mesh/half_edge_ends.h"
#include "core/mesh/union_find.h"
#include "core/prepare/fill_refinement.h"

namespace spheremap {
namespace {

uint64_t edge_key(uint32_t a, uint32_t b) {
  return undirected_edge_key(a, b);
}

double triangle_area(const PolygonMesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  return 0.5 *
         norm(cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]));
}

// The boundary loops: half-edges a -> b with no b -> a, chained b -> next. Loops through a
// vertex with two boundary half-edges out of it (pinched) are not returned.
std::vector<std::vector<uint32_t>> boundary_loops(const PolygonMesh& mesh, size_t& pinched) {
  const HalfEdgeEnds outgoing(mesh);
  std::unordered_map<uint32_t, uint32_t> next;
  std::unordered_set<uint32_t> ambiguous;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      if (outgoing.has(b, a)) continue;
      if (!next.emplace(a, b).second) ambiguous.insert(a);
    }
  }
  std::vector<std::vector<uint32_t>> loops;
  std::unordered_set<uint32_t> seen;
  for (const auto& [start, unused] : next) {
    if (seen.count(start)) continue;
    std::vector<uint32_t> loop;
    bool usable = true;
    uint32_t v = start;
    while (!seen.count(v)) {
      seen.insert(v);
      loop.push_back(v);
      usable = usable && !ambiguous.count(v);
      const auto it = next.find(v);
      if (it == next.end()) {  // an open chain: not a loop
        usable = false;
        break;
      }
      v = it->second;
    }
    if (v != start) usable = false;  // ran into another loop's corner
    if (usable && loop.size() >= 3)
      loops.push_back(std::move(loop));
    else
      ++pinched;
  }
  // Sorted for a result that does not depend on the hash order.
  for (auto& loop : loops)
    std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  std::sort(loops.begin(), loops.end());
  return loops;
}

}  // namespace

std::vector<Triangle> least_area_fill(const PolygonMesh& mesh, std::span<const uint32_t> loop,
                                      const std::unordered_set<uint64_t>& edges, double& area,
                                      const StopCheck* stop, double min_area) {
  const size_t n = loop.size();
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> best(n * n, kNone);
  std::vector<uint32_t> split(n * n, 0);
  for (size_t i = 0; i + 1 < n; ++i) best[i * n + i + 1] = 0;
  for (size_t span = 2; span < n; ++span) {
    if (stop) stop->check();
    for (size_t i = 0; i + span < n; ++i) {
      const size_t k = i + span;
      // The chord i-k (other than the loop's closing edge 0-(n-1)) must be new.
      if (!(i == 0 && k == n - 1) && edges.count(edge_key(loop[i], loop[k]))) continue;
      for (size_t j = i + 1; j < k; ++j) {
        const double a = best[i * n + j], b = best[j * n + k];
        if (a == kNone || b == kNone) continue;
        const double triangle = triangle_area(mesh, loop[i], loop[j], loop[k]);
        if (!(triangle > min_area)) continue;
        const double total = a + b + triangle;
        if (total < best[i * n + k]) {
          best[i * n + k] = total;
          split[i * n + k] = static_cast<uint32_t>(j);
        }
      }
    }
  }
  std::vector<Triangle> out;
  if (best[n - 1] == kNone) return out;
  area = best[n - 1];
  std::vector<std::pair<size_t, size_t>> todo = {{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, k] = todo.back();
    todo.pop_back();
    if (k - i < 2) continue;
    const size_t j = split[i * n + k];
    // The loop runs the way its faces do, so the fill runs against it.
    out.push_back({loop[i], loop[k], loop[j]});
    todo.push_back({i, j});
    todo.push_back({j, k});
  }
  return out;
}

HoleFilling fill_holes(PolygonMesh& mesh, double max_fill, const StopCheck* stop, bool refine,
                       const KeepHoleOpen& keep_open) {
  HoleFilling result;
  if (max_fill <= 0) return result;
  size_t pinched = 0;
  const std::vector<std::vector<uint32_t>> loops = boundary_loops(mesh, pinched);
  result.holes_left = pinched;
  if (loops.empty()) return result;
  // Each hole is weighed against the surface of its own part (an asset's small part with a
  // large hole is not closed because the asset is large).
  UnionFind parts(mesh.vertex_count());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) parts.unite(mesh.face(f)[0], v);
  std::vector<double> surface(mesh.vertex_count(), 0);
  for (const Triangle& t : fan_triangulate(mesh).triangles)
    surface[parts.find(t[0])] += triangle_area(mesh, t[0], t[1], t[2]);
  // The edges a fill must not repeat: the fills ask only for chords between corners of
  // their own loop (and their new vertices, which have no mesh edges), so the mesh's edges
  // between two loop corners are all they need.
  std::vector<char> on_loop(mesh.vertex_count(), 0);
  for (const std::vector<uint32_t>& loop : loops)
    for (uint32_t v : loop) on_loop[v] = 1;
  std::unordered_set<uint64_t> edges;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      if (on_loop[a] && on_loop[b]) edges.insert(edge_key(a, b));
    }
  }
  // Each corner's neighbours in the mesh (before any fill): the fixed ring of the fairing.
  std::unordered_map<uint32_t, std::vector<uint32_t>> ring;
  if (refine) {
    for (const std::vector<uint32_t>& loop : loops)
      for (uint32_t v : loop) ring[v];
    for (size_t f = 0; f < mesh.face_count(); ++f) {
      const auto face = mesh.face(f);
      for (size_t k = 0; k < face.size(); ++k) {
        const uint32_t a = face[k], b = face[(k + 1) % face.size()];
        if (on_loop[a]) ring[a].push_back(b);
        if (on_loop[b]) ring[b].push_back(a);
      }
    }
  }
  if (stop) stop->check();
  for (const std::vector<uint32_t>& loop : loops) {
    double area = 0;
    std::vector<Triangle> fill;
    if (loop.size() <= kMaxHoleCorners) fill = least_area_fill(mesh, loop, edges, area, stop);
    const double part_surface = surface[parts.find(loop[0])];
    const double share = part_surface > 0 ? area / part_surface : INFINITY;
    // A fill with a triangle of next to no area spans a crack (a vertex stored twice, a
    // T-junction): a weld closes that without a degenerate face, so it is left for the weld
    // tolerance prepare offers.
    const bool crack = std::any_of(fill.begin(), fill.end(), [&](const Triangle& t) {
      return !(triangle_area(mesh, t[0], t[1], t[2]) > kCrackArea * part_surface);
    });
    if (fill.empty() || crack || !(share <= max_fill)) {
      ++result.holes_left;
      if (!fill.empty() && !crack && std::isfinite(share)) {
        ++result.holes_too_large;
        result.largest_left_fill = std::max(result.largest_left_fill, share);
      }
      continue;
    }
    if (keep_open && keep_open(loop, fill)) {
      ++result.holes_left;
      ++result.holes_kept_open;
      continue;
    }
    if (refine) {
      const FillRefinement refined =
          refine_and_fair_fill(mesh, loop, fill, edges, ring, fill_vertex_budget(mesh, loop), stop);
      result.vertices_added += refined.vertices_added;
      result.holes_faired += refined.faired;
    }
    for (const Triangle& t : fill) {
      mesh.add_face(t);
      for (int k = 0; k < 3; ++k) edges.insert(edge_key(t[k], t[(k + 1) % 3]));
    }
    ++result.holes_filled;
    result.faces_added += fill.size();
    result.largest_fill = std::max(result.largest_fill, share);
    result.filled_area += share;
  }
  return result;
}

}  // namespace spheremap
