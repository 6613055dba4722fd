#include "core/prepare/handle_closing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "core/mesh/union_find.h"
#include "core/prepare/handle_cycles.h"
#include "core/prepare/hole_filling.h"

namespace spheremap {
namespace {

// Bases rooted at this many vertices are tried each time (the first, then farthest ones):
// the shortest cycle through one root may be long where another root lies on a short one.
constexpr size_t kRoots = 3;
// The shortest cycles tried for one cut (each costs a connectivity pass and two fills of up
// to kMaxHoleCorners^3 / 6 steps): when none of them can be cut, the part is left.
constexpr size_t kMaxTries = 8;

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// The face of a corner (a slot in mesh.indices).
uint32_t face_of_slot(const PolygonMesh& mesh, uint32_t slot) {
  return static_cast<uint32_t>(std::upper_bound(mesh.offsets.begin(), mesh.offsets.end(), slot) -
                               mesh.offsets.begin() - 1);
}

// The vertex of the corner before `slot` in its face (O(log faces), whatever the face's size).
uint32_t before(const PolygonMesh& mesh, uint32_t slot) {
  const uint32_t f = face_of_slot(mesh, slot);
  const uint32_t size = mesh.offsets[f + 1] - mesh.offsets[f];
  return mesh.indices[mesh.offsets[f] + (slot - mesh.offsets[f] + size - 1) % size];
}

// One part's faces as half-edges (a -> b: the face running a -> b), when they form a
// closed surface, manifold at every edge and vertex, consistently oriented; and its genus.
struct PartSurface {
  bool closable = false;
  long long genus = 0;
  std::unordered_map<uint64_t, uint32_t> corner_at;  // directed_edge_key(a, b) -> the slot of a
};

PartSurface part_surface(const PolygonMesh& mesh, const std::vector<uint32_t>& faces,
                         const StopCheck* stop) {
  PartSurface s;
  std::unordered_map<uint32_t, std::pair<uint32_t, uint32_t>> corners;  // v -> (count, a slot)
  for (uint32_t f : faces) {
    const uint32_t size = mesh.offsets[f + 1] - mesh.offsets[f];
    for (uint32_t k = 0; k < size; ++k) {
      const uint32_t slot = mesh.offsets[f] + k;
      const uint32_t a = mesh.indices[slot], b = mesh.indices[mesh.offsets[f] + (k + 1) % size];
      // Twice the same way: inconsistent orientation, a non-manifold edge or a repeated
      // corner.
      if (a == b || !s.corner_at.emplace(directed_edge_key(a, b), slot).second) return s;
      auto& [count, some_slot] = corners.try_emplace(a, 0u, slot).first->second;
      ++count;
    }
  }
  if (stop) stop->check();
  for (const auto& [key, slot] : s.corner_at)
    if (!s.corner_at.count(
            directed_edge_key(static_cast<uint32_t>(key), static_cast<uint32_t>(key >> 32))))
      return s;  // a boundary edge
  // Each vertex's faces form one fan: turning about it from one corner meets them all.
  for (const auto& [v, count_slot] : corners) {
    const auto [count, start] = count_slot;
    uint32_t slot = start, steps = 0;
    do {
      slot = s.corner_at.at(directed_edge_key(v, before(mesh, slot)));
      if (++steps > count) return s;
    } while (slot != start);
    if (steps != count) return s;
  }
  const long long euler = static_cast<long long>(corners.size()) -
                          static_cast<long long>(s.corner_at.size() / 2) +
                          static_cast<long long>(faces.size());
  if (euler > 2 || (2 - euler) % 2 != 0) return s;
  s.closable = true;
  s.genus = (2 - euler) / 2;
  return s;
}

// Whether the part's faces stay connected across every edge but the cycle's.
bool leaves_connected(const PolygonMesh& mesh, const PartSurface& s,
                      const std::vector<uint32_t>& faces, const std::vector<uint32_t>& cycle) {
  std::unordered_map<uint32_t, uint32_t> local;
  for (uint32_t k = 0; k < faces.size(); ++k) local.emplace(faces[k], k);
  std::unordered_set<uint64_t> cut;
  for (size_t k = 0; k < cycle.size(); ++k)
    cut.insert(undirected_edge_key(cycle[k], cycle[(k + 1) % cycle.size()]));
  UnionFind sets(faces.size());
  size_t joined = 0;
  for (const auto& [key, slot] : s.corner_at) {
    const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
    if (a > b || cut.count(undirected_edge_key(a, b))) continue;
    const uint32_t x = sets.find(local.at(face_of_slot(mesh, slot))),
                   y = sets.find(
                       local.at(face_of_slot(mesh, s.corner_at.at(directed_edge_key(b, a)))));
    if (x != y) sets.unite(x, y), ++joined;
  }
  return joined + 1 == faces.size();
}

double area(const PolygonMesh& mesh, const Triangle& t) {
  return 0.5 * norm(cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                          mesh.positions[t[2]] - mesh.positions[t[0]]));
}

// Cuts the part along `cycle` (its vertices copied for the faces on its left, those
// running c[i] -> c[i+1]) and fills both sides; on failure the mesh is as it was. Returns
// the faces added (0: not cut).
size_t cut_and_fill(PolygonMesh& mesh, std::vector<uint32_t>& faces, const PartSurface& s,
                    const std::vector<uint32_t>& cycle, double surface, HandleClosing& result,
                    uint32_t original_vertices, const StopCheck* stop) {
  const size_t n = cycle.size();
  // Per left face corner on the cycle: (index slot in mesh.indices, position on the cycle).
  std::vector<std::pair<uint32_t, uint32_t>> left;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t v = cycle[i], next = cycle[(i + 1) % n], prev = cycle[(i + n - 1) % n];
    const auto it = s.corner_at.find(directed_edge_key(v, next));
    if (it == s.corner_at.end()) return 0;
    uint32_t slot = it->second;
    for (size_t steps = 0;; ++steps) {
      if (steps > faces.size()) return 0;
      left.push_back({slot, i});
      const uint32_t a = before(mesh, slot);
      if (a == prev) break;
      slot = s.corner_at.at(directed_edge_key(v, a));
    }
  }
  const uint32_t first_copy = static_cast<uint32_t>(mesh.vertex_count());
  for (uint32_t v : cycle) {
    const Vec3 position = mesh.positions[v];
    mesh.positions.push_back(position);
    result.copy_of.push_back(v < original_vertices ? v : result.copy_of[v - original_vertices]);
  }
  for (const auto& [slot, i] : left) mesh.indices[slot] = first_copy + i;
  auto undo = [&] {
    for (const auto& [slot, i] : left) mesh.indices[slot] = cycle[i];
    mesh.positions.resize(first_copy);
    result.copy_of.resize(first_copy - original_vertices);
  };
  std::unordered_set<uint64_t> edges;
  for (uint32_t f : faces) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      edges.insert(undirected_edge_key(face[k], face[(k + 1) % face.size()]));
  }
  // The left side's boundary runs c[i]' -> c[i+1]' (the way its faces do), the right
  // side's c[i+1] -> c[i].
  std::vector<uint32_t> left_loop(n), right_loop(cycle.rbegin(), cycle.rend());
  for (uint32_t i = 0; i < n; ++i) left_loop[i] = first_copy + i;
  std::vector<Triangle> fill;
  for (const auto* loop : {&left_loop, &right_loop}) {
    double unused = 0;
    // Collinear corners (common along CAD edges) would give triangles of no area: such
    // triangles are not used, so the fill goes around them.
    const std::vector<Triangle> side =
        least_area_fill(mesh, *loop, edges, unused, stop, kCrackArea * surface);
    const bool crack = std::any_of(side.begin(), side.end(), [&](const Triangle& t) {
      return !(area(mesh, t) > kCrackArea * surface);
    });
    if (side.empty() || crack) {
      undo();
      return 0;
    }
    fill.insert(fill.end(), side.begin(), side.end());
  }
  for (const Triangle& t : fill) {
    faces.push_back(static_cast<uint32_t>(mesh.face_count()));
    mesh.add_face(t);
  }
  return fill.size();
}

// Closes the handles of one part while the bounds allow; returns why it stopped ("" when
// it reached genus 0) and leaves the genus left in `genus`.
std::string close_part(PolygonMesh& mesh, std::vector<uint32_t>& faces, long long& genus,
                       double max_cycle, size_t max_genus, HandleClosing& result,
                       uint32_t original_vertices, const StopCheck* stop) {
  Vec3 low{INFINITY, INFINITY, INFINITY}, high{-INFINITY, -INFINITY, -INFINITY};
  double surface = 0;
  for (uint32_t f : faces) {
    const auto face = mesh.face(f);
    for (uint32_t v : face) {
      const Vec3& p = mesh.positions[v];
      low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
      high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
    }
    for (size_t k = 1; k + 1 < face.size(); ++k)
      surface += area(mesh, {face[0], face[k], face[k + 1]});
  }
  const double diagonal = norm(high - low);
  if (!(diagonal > 0)) return "its bounding box has no extent";
  while (genus > 0) {
    if (stop) stop->check();
    const size_t cap = std::min(max_genus, kHandleWork / std::max<size_t>(faces.size(), 1));
    if (static_cast<size_t>(genus) > cap)
      return "its genus " + std::to_string(genus) + " is above the " + std::to_string(cap) +
             " handles closed in a part of " + std::to_string(faces.size()) + " faces (at most " +
             std::to_string(max_genus) + ", and faces x handles at most " +
             std::to_string(kHandleWork) + ")";
    const PartSurface s = part_surface(mesh, faces, stop);
    if (!s.closable || s.genus != genus) return "its surface changed while closing";
    const std::vector<HandleCycle> cycles = handle_cycles(mesh, faces, kRoots, stop);
    size_t tried = 0, long_ones = 0, separating = 0, unfilled = 0;
    bool closed = false;
    for (const HandleCycle& cycle : cycles) {
      const double relative = cycle.length / diagonal;
      if (!(relative <= max_cycle)) {
        if (tried > 0) break;
        return "the shortest non-separating cycle left is " + number(relative) +
               " of the part's bounding-box diagonal long, above max_handle_cycle " +
               number(max_cycle);
      }
      if (tried == kMaxTries) break;
      ++tried;
      if (cycle.vertices.size() < 3 || cycle.vertices.size() > kMaxHoleCorners) {
        ++long_ones;
        continue;
      }
      if (!leaves_connected(mesh, s, faces, cycle.vertices)) {
        ++separating;
        continue;
      }
      const size_t added =
          cut_and_fill(mesh, faces, s, cycle.vertices, surface, result, original_vertices, stop);
      if (added == 0) {
        ++unfilled;
        continue;
      }
      ++result.handles_closed;
      result.faces_added += added;
      result.largest_cycle = std::max(result.largest_cycle, relative);
      closed = true;
      break;
    }
    if (!closed)
      return "none of its " + std::to_string(tried) + " shortest non-separating cycles within " +
             "max_handle_cycle " + number(max_cycle) + " could be cut and filled (" +
             std::to_string(long_ones) + " of more than " + std::to_string(kMaxHoleCorners) +
             " corners, " + std::to_string(separating) + " that would split the part, " +
             std::to_string(unfilled) +
             " without a fill of both sides free of non-manifold edges and triangles of no "
             "area)";
    --genus;
  }
  return "";
}

}  // namespace

HandleClosing close_handles(PolygonMesh& mesh, double max_cycle, const StopCheck* stop,
                            size_t max_genus) {
  HandleClosing result;
  if (!(max_cycle > 0) || mesh.face_count() == 0) return result;
  const uint32_t original_vertices = static_cast<uint32_t>(mesh.vertex_count());
  UnionFind sets(original_vertices);
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  // Each part's faces, parts in the order of their first face.
  std::unordered_map<uint32_t, size_t> part_of_root;
  std::vector<std::vector<uint32_t>> parts;
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const auto [it, added] = part_of_root.emplace(sets.find(mesh.face(f)[0]), parts.size());
    if (added) parts.emplace_back();
    parts[it->second].push_back(f);
  }
  for (std::vector<uint32_t>& faces : parts) {
    const PartSurface s = part_surface(mesh, faces, stop);
    if (!s.closable || s.genus <= 0) continue;
    long long genus = s.genus;
    const uint32_t some_vertex = mesh.face(faces[0])[0];
    std::string reason =
        close_part(mesh, faces, genus, max_cycle, max_genus, result, original_vertices, stop);
    if (genus == 0) continue;
    result.handles_left += static_cast<size_t>(genus);
    result.stopped.push_back({some_vertex, static_cast<size_t>(genus), std::move(reason)});
  }
  return result;
}

}  // namespace spheremap
