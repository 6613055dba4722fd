// Refining and fairing one hole's fill (Liepa 2003, "Filling holes in meshes", §3-4): the
// least-area triangulation of hole_filling.h spans a wide hole with long thin triangles in
// a flat (or folded) sheet; here its triangles are split where they are larger than the
// boundary's edges say they should be, edges are swapped toward Delaunay, and the new
// vertices are moved to the thin-plate surface (scale-dependent bi-Laplacian, the boundary loop and
// the mesh's ring around it fixed), so the cap continues the surface around the hole. No
// vertex of the mesh moves; new vertices are appended to mesh.positions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

// Liepa's density factor: a fill triangle is split while its centroid is farther than
// sigma / alpha from each corner (sigma: the mean edge length the boundary asks there).
inline constexpr double kFillDensity = 1.4142135623730951;  // sqrt(2), as in the paper
// The most vertices one hole's fill may add, whatever its boundary asks.
inline constexpr size_t kMaxFillVertices = 20000;

// The new vertices a hole with this boundary may get: about 2.7x what a flat disc of its
// perimeter needs at the boundary's mean edge length ((perimeter / mean edge)^2 / 4,
// against corners^2 / (2 pi sqrt 3)), at most kMaxFillVertices.
size_t fill_vertex_budget(const PolygonMesh& mesh, std::span<const uint32_t> loop);

struct FillRefinement {
  size_t vertices_added = 0;
  size_t swaps = 0;
  bool faired = false;  // false: the thin-plate positions would fold, the refined flat kept
};

// Refines `fill` (triangles over `loop`'s corners, as least_area_fill returns them) and
// fairs its new vertices. `edges`: the undirected edges (undirected_edge_key) the mesh has
// besides the fill's, so no swap makes an edge twice. `ring`: per corner of `loop`, its
// neighbours in the mesh (the fixed second ring of the thin-plate system; a corner without
// any makes the fairing a membrane there). At most `max_vertices` are added. On return
// `fill` holds the new triangles, running the way the old did; the new vertices are
// mesh.positions[old vertex_count ...]. `stop` may be null.
FillRefinement refine_and_fair_fill(PolygonMesh& mesh, std::span<const uint32_t> loop,
                                    std::vector<Triangle>& fill,
                                    const std::unordered_set<uint64_t>& edges,
                                    const std::unordered_map<uint32_t, std::vector<uint32_t>>& ring,
                                    size_t max_vertices, const StopCheck* stop);

}  // namespace spheremap
