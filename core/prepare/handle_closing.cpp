#include "core/prepare/handle_closing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "core/mesh/triangle_tree.h"
#include "core/mesh/union_find.h"
#include "core/prepare/handle_cycles.h"
#include "core/prepare/hole_filling.h"
#include "core/prepare/vertex_corners.h"

namespace spheremap {
namespace {

// Bases rooted at this many vertices are tried each time (the first, then farthest ones):
// the shortest cycle through one root may be long where another root lies on a short one.
constexpr size_t kRoots = 3;
// The shortest distinct cycles weighed for one cut (each costs a fill of up to
// kMaxHoleCorners^3 / 6 steps, and a connectivity pass and two fills when tried): when none
// of them can be cut, the part is left.
constexpr size_t kMaxAlternatives = 16;
// The most cuts made and measured for one handle when no fill is near (each costs a
// connectivity pass, two fills and the sampling of them).
constexpr size_t kMeasuredCuts = 4;
// A fill within this share of the part's diagonal of its own surface is near enough: a
// remesh through it stays within half of Reach II's 2%.
constexpr double kNearFill = 0.01;

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// One part's faces by corner (vertex_corners.h), when they form a closed surface, manifold
// at every edge and vertex, consistently oriented; and its genus.
struct PartSurface {
  bool closable = false;
  long long genus = 0;
  VertexCorners corners;
};

PartSurface part_surface(const PolygonMesh& mesh, const std::vector<uint32_t>& faces,
                         const StopCheck* stop) {
  PartSurface s;
  // An edge run twice the same way (inconsistent orientation, a non-manifold edge) or a
  // repeated corner: not closable.
  std::optional<VertexCorners> corners = VertexCorners::of_faces(mesh, faces);
  if (!corners) return s;
  s.corners = std::move(*corners);
  if (stop) stop->check();
  const size_t vertices = s.corners.vertex_capacity();
  for (uint32_t v = 0; v < vertices; ++v)
    for (const VertexCorner& c : s.corners.at(v))
      if (!s.corners.find(c.next, v)) return s;  // a boundary edge
  // Each vertex's faces form one fan: turning about it from one corner meets them all.
  for (uint32_t v = 0; v < vertices; ++v) {
    const std::span<const VertexCorner> row = s.corners.at(v);
    if (row.empty()) continue;
    const VertexCorner* corner = &row[0];
    size_t steps = 0;
    do {
      corner = s.corners.find(v, corner->prev);  // the face running v -> prev: the next one
      if (++steps > row.size()) return s;
    } while (corner != &row[0]);
    if (steps != row.size()) return s;
  }
  const long long euler = static_cast<long long>(s.corners.vertices()) -
                          static_cast<long long>(s.corners.corners() / 2) +
                          static_cast<long long>(faces.size());
  if (euler > 2 || (2 - euler) % 2 != 0) return s;
  s.closable = true;
  s.genus = (2 - euler) / 2;
  return s;
}

// The part's edges as the pairs of its faces beside them (local ids: positions in the
// part's face list), made once for all the cycles weighed for one cut.
struct EdgeFaces {
  size_t faces = 0;
  std::vector<uint64_t> keys;  // undirected_edge_key
  std::vector<std::pair<uint32_t, uint32_t>> sides;
};

EdgeFaces edge_faces(const PartSurface& s, const std::vector<uint32_t>& faces) {
  EdgeFaces e;
  e.faces = faces.size();
  for (uint32_t a = 0; a < s.corners.vertex_capacity(); ++a)
    for (const VertexCorner& c : s.corners.at(a)) {
      if (a > c.next) continue;
      e.keys.push_back(undirected_edge_key(a, c.next));
      e.sides.push_back({c.face, s.corners.find(c.next, a)->face});
    }
  return e;
}

// Whether the part's faces stay connected across every edge but the cycle's. `on_cycle`:
// per mesh vertex, 1 on the cycle (only an edge with both ends on it is looked up).
bool leaves_connected(const EdgeFaces& e, const std::vector<uint32_t>& cycle,
                      const std::vector<char>& on_cycle) {
  std::unordered_set<uint64_t> cut;
  for (size_t k = 0; k < cycle.size(); ++k)
    cut.insert(undirected_edge_key(cycle[k], cycle[(k + 1) % cycle.size()]));
  UnionFind sets(e.faces);
  size_t joined = 0;
  for (size_t k = 0; k < e.keys.size(); ++k) {
    const uint64_t key = e.keys[k];
    if (on_cycle[key >> 32] && on_cycle[static_cast<uint32_t>(key)] && cut.count(key)) continue;
    const uint32_t x = sets.find(e.sides[k].first), y = sets.find(e.sides[k].second);
    if (x != y) sets.unite(x, y), ++joined;
  }
  return joined + 1 == e.faces;
}

double area(const PolygonMesh& mesh, const Triangle& t) {
  return 0.5 * norm(cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                          mesh.positions[t[2]] - mesh.positions[t[0]]));
}

// What a cut changed, to take it back: the left faces' corners renamed to the copies
// (slot, position on the cycle), and the sizes before it.
struct Cut {
  size_t added = 0;  // fill triangles appended (0: not cut)
  std::vector<uint32_t> cycle;
  std::vector<Triangle> fill;
  std::vector<std::pair<uint32_t, uint32_t>> left;
  uint32_t first_copy = 0;
  size_t mesh_faces = 0, part_faces = 0;
};

void undo_cut(PolygonMesh& mesh, std::vector<uint32_t>& faces, const Cut& cut,
              HandleClosing& result, uint32_t original_vertices) {
  for (const auto& [slot, i] : cut.left) mesh.indices[slot] = cut.cycle[i];
  mesh.positions.resize(cut.first_copy);
  result.copy_of.resize(cut.first_copy - original_vertices);
  mesh.offsets.resize(cut.mesh_faces + 1);
  mesh.indices.resize(mesh.offsets.back());
  faces.resize(cut.part_faces);
}

// Makes a cut again where undo_cut took it back (on the mesh as it was when it was made).
void redo_cut(PolygonMesh& mesh, std::vector<uint32_t>& faces, const Cut& cut,
              HandleClosing& result, uint32_t original_vertices) {
  for (uint32_t v : cut.cycle) {
    const Vec3 position = mesh.positions[v];
    mesh.positions.push_back(position);
    result.copy_of.push_back(v < original_vertices ? v : result.copy_of[v - original_vertices]);
  }
  for (const auto& [slot, i] : cut.left) mesh.indices[slot] = cut.first_copy + i;
  for (const Triangle& t : cut.fill) {
    faces.push_back(static_cast<uint32_t>(mesh.face_count()));
    mesh.add_face(t);
  }
}

// Cuts the part along `cycle` (its vertices copied for the faces on its left, those
// running c[i] -> c[i+1]) and fills both sides; on failure the mesh is as it was. The fill
// is the mesh's faces from cut.mesh_faces on. `edges`: the part's edges (undirected_edge_key)
// before the cut, as they are again on return.
Cut cut_and_fill(PolygonMesh& mesh, std::vector<uint32_t>& faces, const PartSurface& s,
                 const std::vector<uint32_t>& cycle, std::unordered_set<uint64_t>& edges,
                 double surface, HandleClosing& result, uint32_t original_vertices,
                 const StopCheck* stop) {
  Cut cut;
  cut.cycle = cycle;
  const size_t n = cycle.size();
  // Per left face corner on the cycle: (index slot in mesh.indices, position on the cycle).
  std::vector<std::pair<uint32_t, uint32_t>>& left = cut.left;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t v = cycle[i], next = cycle[(i + 1) % n], prev = cycle[(i + n - 1) % n];
    const VertexCorner* corner = s.corners.find(v, next);
    for (size_t steps = 0;; ++steps) {
      if (!corner || steps > faces.size()) return {};
      left.push_back({corner->slot, i});
      if (corner->prev == prev) break;
      corner = s.corners.find(v, corner->prev);
    }
  }
  cut.first_copy = static_cast<uint32_t>(mesh.vertex_count());
  cut.mesh_faces = mesh.face_count();
  cut.part_faces = faces.size();
  const uint32_t first_copy = cut.first_copy;
  for (uint32_t v : cycle) {
    const Vec3 position = mesh.positions[v];
    mesh.positions.push_back(position);
    result.copy_of.push_back(v < original_vertices ? v : result.copy_of[v - original_vertices]);
  }
  // The part's edges after the cut, from `edges` (before it): the left faces' edges renamed
  // (an edge off the cycle has both its faces on one side; the cycle's own edges stay, on
  // the right side's faces).
  std::unordered_set<uint64_t> cycle_edges;
  for (size_t i = 0; i < n; ++i)
    cycle_edges.insert(undirected_edge_key(cycle[i], cycle[(i + 1) % n]));
  std::vector<uint32_t> left_faces;
  for (const auto& [slot, i] : left) left_faces.push_back(face_of_slot(mesh, slot));
  std::sort(left_faces.begin(), left_faces.end());
  left_faces.erase(std::unique(left_faces.begin(), left_faces.end()), left_faces.end());
  std::vector<uint64_t> removed, added;
  auto each_edge = [&](auto&& visit) {
    for (uint32_t f : left_faces) {
      const auto face = mesh.face(f);
      for (size_t k = 0; k < face.size(); ++k)
        visit(undirected_edge_key(face[k], face[(k + 1) % face.size()]));
    }
  };
  each_edge([&](uint64_t key) {
    if (!cycle_edges.count(key) && edges.erase(key)) removed.push_back(key);
  });
  for (const auto& [slot, i] : left) mesh.indices[slot] = first_copy + i;
  each_edge([&](uint64_t key) {
    if (edges.insert(key).second) added.push_back(key);
  });
  auto restore_edges = [&] {
    for (uint64_t key : added) edges.erase(key);
    edges.insert(removed.begin(), removed.end());
  };
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
      restore_edges();
      undo_cut(mesh, faces, cut, result, original_vertices);
      return {};
    }
    fill.insert(fill.end(), side.begin(), side.end());
  }
  restore_edges();
  for (const Triangle& t : fill) {
    faces.push_back(static_cast<uint32_t>(mesh.face_count()));
    mesh.add_face(t);
  }
  cut.added = fill.size();
  cut.fill = std::move(fill);
  return cut;
}

// The part's own faces (those below `own_faces`: not fills of holes or earlier cuts), as a
// tree for the distance of a cut's fill to them.
TriangleTree own_surface(const PolygonMesh& mesh, const std::vector<uint32_t>& faces,
                         size_t own_faces) {
  std::vector<uint32_t> own;
  std::copy_if(faces.begin(), faces.end(), std::back_inserter(own),
               [&](uint32_t f) { return f < own_faces; });
  return polygon_tree(mesh, own);
}

// How far the fill a cut appended (the mesh's faces from `first_fill` on) strays from the
// part's own surface.
double fill_distance(const PolygonMesh& mesh, size_t first_fill, const TriangleTree& own) {
  std::vector<Triangle> fill;
  for (size_t f = first_fill; f < mesh.face_count(); ++f)
    fill.push_back({mesh.face(f)[0], mesh.face(f)[1], mesh.face(f)[2]});
  return farthest_from(own, mesh.positions, fill);
}

struct Candidate {
  const HandleCycle* cycle = nullptr;
  double distance = INFINITY;  // of its fill from the part's own surface (estimated)
};

// The cycles to try for the next cut, in order: up to kMaxAlternatives distinct ones of at
// most `max_length`; first those whose fill lies within `near` of the part's own surface,
// shortest first, then the others, nearest first. The shortest cycle is often the rim of a
// through-hole, whose cap is as far from the part as the hole is wide, where a cycle through
// the hole and around the wall beside it (longer) is capped inside the material, as far as
// the wall is thin. A fill is estimated on the uncut surface (one side: both have the same
// corners); cycles too long to fill come last.
std::vector<Candidate> nearest_fills_first(const PolygonMesh& mesh,
                                           const std::vector<HandleCycle>& cycles,
                                           double max_length, double near, double surface,
                                           const std::unordered_set<uint64_t>& edges,
                                           const TriangleTree& own, const StopCheck* stop) {
  std::vector<Candidate> candidates;
  std::set<std::vector<uint32_t>> seen;  // bases from several roots repeat cycles
  for (const HandleCycle& cycle : cycles) {
    if (!(cycle.length <= max_length) || candidates.size() == kMaxAlternatives) break;
    std::vector<uint32_t> sorted = cycle.vertices;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(std::move(sorted)).second) continue;
    Candidate candidate{&cycle};
    // With no bound on near (shortest first), every cycle is near: nothing to estimate.
    if (std::isfinite(near) && cycle.vertices.size() >= 3 &&
        cycle.vertices.size() <= kMaxHoleCorners) {
      const std::vector<uint32_t> loop(cycle.vertices.rbegin(), cycle.vertices.rend());
      double unused = 0;
      const std::vector<Triangle> fill =
          least_area_fill(mesh, loop, edges, unused, stop, kCrackArea * surface);
      if (!fill.empty()) candidate.distance = farthest_from(own, mesh.positions, fill);
    }
    candidates.push_back(candidate);
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](const Candidate& a, const Candidate& b) {
                     const bool a_near = a.distance <= near, b_near = b.distance <= near;
                     if (a_near || b_near) return a_near && !b_near;
                     return a.distance < b.distance;
                   });
  return candidates;
}

// One part's closing: the cuts made, in order, and how far the farthest fill stands from
// the part (over its diagonal).
struct PartCuts {
  std::vector<Cut> cuts;
  double farthest = 0;
};

// Closes the handles of one part while the bounds allow, taking for each cut the first of
// the cycles weighed whose fill lies within `near` of the part (a share of its diagonal;
// infinity: the shortest that can be cut), else the nearest; returns why it stopped (""
// when it reached genus 0) and leaves the genus left in `genus`.
std::string close_part(PolygonMesh& mesh, std::vector<uint32_t>& faces, long long& genus,
                       double max_cycle, size_t max_genus, size_t own_faces, double near,
                       HandleClosing& result, uint32_t original_vertices, PartCuts& made,
                       const StopCheck* stop) {
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
  std::optional<TriangleTree> own;  // the part's own faces: the same after every cut
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
    if (!cycles.empty() && !(cycles.front().length / diagonal <= max_cycle))
      return "the shortest non-separating cycle left is " +
             number(cycles.front().length / diagonal) +
             " of the part's bounding-box diagonal long, above max_handle_cycle " +
             number(max_cycle);
    if (!own) own.emplace(own_surface(mesh, faces, own_faces));
    const EdgeFaces sides = edge_faces(s, faces);
    // The part's edges a fill must not repeat: a fill asks only for chords between corners
    // of its own loop (as hole_filling's do), so only the edges between vertices of the
    // cycles weighed are kept (the edges of the copies a cut makes are added by the cut).
    std::vector<char> on_cycles(mesh.vertex_count(), 0), on_cycle(mesh.vertex_count(), 0);
    for (const HandleCycle& cycle : cycles)
      for (uint32_t v : cycle.vertices) on_cycles[v] = 1;
    std::unordered_set<uint64_t> edges;
    for (uint64_t key : sides.keys)
      if (on_cycles[key >> 32] && on_cycles[static_cast<uint32_t>(key)]) edges.insert(key);
    const std::vector<Candidate> candidates = nearest_fills_first(
        mesh, cycles, max_cycle * diagonal, near * diagonal, surface, edges, *own, stop);
    size_t tried = 0, long_ones = 0, separating = 0, unfilled = 0, measured = 0;
    // Cuts are made and measured (then taken back) in that order: the first whose fill is
    // near is kept, else the nearest of the first kMeasuredCuts (the estimate leaves out
    // the other side's fill, and the real fills may use chords the uncut surface forbids).
    const HandleCycle* best = nullptr;
    Cut best_cut;
    double best_distance = INFINITY;
    for (const Candidate& candidate : candidates) {
      const HandleCycle& cycle = *candidate.cycle;
      if (measured == kMeasuredCuts) break;
      ++tried;
      if (cycle.vertices.size() < 3 || cycle.vertices.size() > kMaxHoleCorners) {
        ++long_ones;
        continue;
      }
      for (uint32_t v : cycle.vertices) on_cycle[v] = 1;
      const bool connected = leaves_connected(sides, cycle.vertices, on_cycle);
      for (uint32_t v : cycle.vertices) on_cycle[v] = 0;
      if (!connected) {
        ++separating;
        continue;
      }
      const Cut cut = cut_and_fill(mesh, faces, s, cycle.vertices, edges, surface, result,
                                   original_vertices, stop);
      if (cut.added == 0) {
        ++unfilled;
        continue;
      }
      ++measured;
      const double distance = fill_distance(mesh, cut.mesh_faces, *own);
      undo_cut(mesh, faces, cut, result, original_vertices);
      if (distance < best_distance) best = &cycle, best_cut = cut, best_distance = distance;
      if (distance <= near * diagonal) break;
    }
    if (!best)
      return "none of its " + std::to_string(tried) + " shortest non-separating cycles within " +
             "max_handle_cycle " + number(max_cycle) + " could be cut and filled (" +
             std::to_string(long_ones) + " of more than " + std::to_string(kMaxHoleCorners) +
             " corners, " + std::to_string(separating) + " that would split the part, " +
             std::to_string(unfilled) +
             " without a fill of both sides free of non-manifold edges and triangles of no "
             "area)";
    // Made again on the mesh it was measured on (each measured cut was undone).
    redo_cut(mesh, faces, best_cut, result, original_vertices);
    ++result.handles_closed;
    result.faces_added += best_cut.added;
    result.largest_cycle = std::max(result.largest_cycle, best->length / diagonal);
    made.farthest = std::max(made.farthest, best_distance / diagonal);
    made.cuts.push_back(std::move(best_cut));
    --genus;
  }
  return "";
}

}  // namespace

HandleClosing close_handles(PolygonMesh& mesh, double max_cycle, const StopCheck* stop,
                            size_t max_genus, size_t own_faces) {
  HandleClosing result;
  own_faces = std::min(own_faces, mesh.face_count());
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
  // Each part's V - H / 2 + F (H: its corners): its Euler characteristic when it is a closed
  // surface. At 2 or more it has no handle, closable or not, and part_surface (a hash map of
  // its corners) is skipped: most of the preparation of a kit of 1,024 closed parts.
  std::vector<int64_t> twice_euler(parts.size(), 0);
  for (size_t k = 0; k < parts.size(); ++k)
    for (uint32_t f : parts[k]) twice_euler[k] += 2 - static_cast<int64_t>(mesh.face_size(f));
  std::vector<char> counted(original_vertices, 0);
  for (size_t k = 0; k < parts.size(); ++k)
    for (uint32_t f : parts[k])
      for (uint32_t v : mesh.face(f))
        if (!counted[v]) counted[v] = 1, twice_euler[k] += 2;
  for (size_t k = 0; k < parts.size(); ++k) {
    std::vector<uint32_t>& faces = parts[k];
    if (twice_euler[k] >= 4) continue;
    const PartSurface s = part_surface(mesh, faces, stop);
    if (!s.closable || s.genus <= 0) continue;
    const uint32_t some_vertex = mesh.face(faces[0])[0];
    // Each cut takes the nearest fill, which can leave the next handles only far ones: when
    // a fill stands far, the part is closed again shortest first (as before fills were
    // weighed), and the closing whose farthest fill is nearer is kept (at equal genus).
    const std::vector<uint32_t> part_faces = faces;
    const HandleClosing before = result;
    auto close = [&](double near, long long& genus, PartCuts& made) {
      genus = s.genus;
      return close_part(mesh, faces, genus, max_cycle, max_genus, own_faces, near, result,
                        original_vertices, made, stop);
    };
    auto undo = [&](const PartCuts& made) {
      for (auto cut = made.cuts.rbegin(); cut != made.cuts.rend(); ++cut)
        undo_cut(mesh, faces, *cut, result, original_vertices);
      faces = part_faces;
      result = before;
    };
    long long genus = 0;
    PartCuts made;
    std::string reason = close(kNearFill, genus, made);
    if (made.farthest > kNearFill) {
      long long shortest_genus = 0;
      PartCuts shortest;
      const HandleClosing nearest_result = result;
      undo(made);
      std::string shortest_reason = close(INFINITY, shortest_genus, shortest);
      if (shortest_genus <= genus && shortest.farthest < made.farthest) {
        genus = shortest_genus, made = std::move(shortest), reason = std::move(shortest_reason);
      } else {  // the first closing again, as it was
        undo(shortest);
        for (const Cut& cut : made.cuts) redo_cut(mesh, faces, cut, result, original_vertices);
        result = nearest_result;
      }
    }
    result.farthest_fill = std::max(result.farthest_fill, made.farthest);
    if (!made.cuts.empty()) {
      size_t fills = 0;
      for (const Cut& cut : made.cuts) fills += cut.added;
      result.closed_parts.push_back(
          {made.cuts.front().mesh_faces, fills, made.cuts.size(), made.farthest, genus != 0});
    }
    if (genus == 0) continue;
    result.handles_left += static_cast<size_t>(genus);
    result.stopped.push_back({some_vertex, static_cast<size_t>(genus), std::move(reason)});
  }
  return result;
}

}  // namespace spheremap
