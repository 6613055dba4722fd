// Closing small holes (Reach I): each boundary loop of a mesh whose fill is small beside the
// surface is closed as Liepa 2003 does: the triangulation of its corners of least total
// area, then refined to the boundary's edge lengths and faired (fill_refinement.h). No
// vertex of the mesh moves; the new vertices are appended after the mesh's own.
// A part with a few holes then maps instead of being left out; the added faces are
// appended after the mesh's own, so outputs that show only the original (the sphere in
// the input's layout) leave them out, and those where closing is the point (the remesh)
// keep them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_set>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

// The most corners a hole may have: the triangulation costs corners^3 / 6 steps.
inline constexpr size_t kMaxHoleCorners = 300;

struct HoleFilling {
  size_t holes_filled = 0, faces_added = 0;
  size_t vertices_added = 0;  // by refining the fills (appended to mesh.positions)
  size_t holes_faired = 0;    // fills whose new vertices lie on the thin-plate surface
  size_t holes_left = 0;      // too large, too many corners, pinched, or no valid triangulation
  double largest_fill = 0;    // the largest fill's area over the surface area of its part
  double filled_area = 0;     // the sum of those shares
  // Holes left only for their size (a fill was found, over max_fill), and the largest such
  // fill's share of its part's surface: the max_fill that would have closed them.
  size_t holes_too_large = 0;
  double largest_left_fill = 0;
  size_t holes_kept_open = 0;  // fillable, but `keep_open` said no (also in holes_left)
};

// Asked of each hole that would be filled (its loop and least-area fill): true leaves it.
using KeepHoleOpen = std::function<bool(std::span<const uint32_t>, std::span<const Triangle>)>;

// Preconditions: `mesh` welded (one vertex per point) and consistently oriented around each
// hole. Fills every hole whose fill area is at most `max_fill` of the surface area of its
// part (connected component), with at most kMaxHoleCorners corners, whose boundary visits
// each corner once, and which can be triangulated without an edge the mesh (or an earlier
// fill) already has (that would make it non-manifold). Holes whose fill would have a
// triangle of next to no area (cracks, which a weld closes) are left. Fills run the way
// the hole's faces do. The size bound is weighed on the least-area fill; `refine` then
// refines and fairs each fill (refine_and_fair_fill, at most fill_vertex_budget new
// vertices per hole); false: the least-area fill alone, no vertex added. A hole for which
// `keep_open` (when set) says true is left (far_hole_fills.h). `stop` may be null.
HoleFilling fill_holes(PolygonMesh& mesh, double max_fill, const StopCheck* stop = nullptr,
                       bool refine = true, const KeepHoleOpen& keep_open = {});

// The key of the undirected edge {a, b} in the `edges` sets below.
inline uint64_t undirected_edge_key(uint32_t a, uint32_t b) {
  return (uint64_t{a < b ? a : b} << 32) | (a < b ? b : a);
}

// The key of the directed edge a -> b (a half-edge), distinct from b -> a.
inline uint64_t directed_edge_key(uint32_t a, uint32_t b) {
  return (uint64_t{a} << 32) | b;
}

// A fill triangle smaller than this share of its part's surface spans a crack.
inline constexpr double kCrackArea = 1e-9;

// The triangles of least total area over a loop's corners (dynamic programming over
// sub-polygons, corners^3 / 6 steps: callers bound `loop` by kMaxHoleCorners), none with an
// edge in `edges` (undirected_edge_key) but the loop's own; empty when there is none.
// `loop` runs the way the faces beside it do; the triangles run against it, so they close
// the surface consistently oriented. `area` receives their total area. Triangles of at most
// `min_area` are not used (a negative bound allows every one). `stop` may be null.
std::vector<Triangle> least_area_fill(const PolygonMesh& mesh, std::span<const uint32_t> loop,
                                      const std::unordered_set<uint64_t>& edges, double& area,
                                      const StopCheck* stop, double min_area = -1);

}  // namespace spheremap
