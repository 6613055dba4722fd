// Open sheets closed by their own back (Reach II, prepare=auto): a part that is a disc (one
// boundary loop, genus 0: a terrain, a plane, a cloth, a head without a neck, a scan with
// its bottom missing) whose hole is too large to fill is glued to a copy of itself facing
// the other way along that boundary. The result is a closed genus-0 surface with no vertex
// moved and no point farther from the original than zero: the zero-thickness limit of the
// thin shell its envelope would be (within an offset of 0.6% of the diagonal, resampled,
// without the part's own vertices), at the cost of a copy.
//
// The back is the front's triangles (polygons fanned as the map fans them) reversed. Its
// corners are the front's boundary vertices, shared, and copies of its interior ones. An
// interior edge or fan diagonal between two boundary vertices would then be shared by four
// triangles, so the back splits it at its midpoint, and a back triangle so split is a fan
// around its centroid: every back point lies on the front.
// The back is appended after the mesh's own faces and vertices, as fills are (hole_filling.h),
// so outputs in the input's layout leave it out; unlike a fill it is weighed alike in the
// map (it is the input's surface again).
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/topology.h"

namespace spheremap {

// Whether a part with this topology (analyze_topology of the part alone) is genus 0 and
// open, its holes all that keep it from mapping; a disc when it has one hole: the parts
// double_open_sheets gives a back (open_part_cuts.h makes the others discs).
bool is_open_sphere(const TopologyReport& topology);
bool is_open_disc(const TopologyReport& topology);

struct SheetDoubling {
  size_t sheets_doubled = 0;
  size_t faces_added = 0, vertices_added = 0;  // the backs' (appended after the mesh's own)
};

// Preconditions: `mesh` welded (one vertex per point). Every connected component whose only
// mapping failure is one boundary loop and whose Euler characteristic is 1 (a disc) gets a
// back; a component whose back would have a fan triangle of no area (around the centroid of
// a front triangle of none), or would not be closed genus 0 (checked), is left as it was (a
// front triangle's mirror may be as flat as it: the map takes both). However many they are: each
// then maps as a part of its own, as a closed fragment would (a scatter of 20,000 quads: 6 s, 350
// MB; wrapped as one, their envelope was a body of merged blobs that did not map), and the parts'
// remesh grids share one budget (part_grids.h). The mesh's own vertices and faces are unchanged.
// O(vertices + corners). `stop` may be null.
SheetDoubling double_open_sheets(PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
