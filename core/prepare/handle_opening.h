// Handles opened instead of capped (Reach II, prepare=auto). close_handles (handle_closing.h)
// cuts a part along non-separating cycles and caps both sides of each cut, taking the cut
// whose cap lies nearest the part. Where even that cap stands far from it (a through-hole's
// cap is as far from the part as the hole is wide; a torus's spans its inner hole), a remesh
// through the caps is as far from the asset: a ring's 4-11% of its diagonal, where Reach II
// asks 2%. Such a part's caps are taken out again and its cuts left open: it is then genus 0
// with two holes per handle, which open_part_cuts.h joins into a disc and sheet_doubling.h
// closes by its own back. No point leaves the surface and no face is added off it; the cost
// is the doubled part's remesh, its samples shared by both sides of the surface.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/prepare/handle_closing.h"

namespace spheremap {

struct HandleOpening {
  size_t parts_opened = 0;
  size_t handles_opened = 0;  // cuts left open, their caps removed
  size_t faces_removed = 0;   // the caps' faces
  double farthest_fill = 0;   // the farthest cap kept, over its part's diagonal
  size_t vertices_split = 0;  // where two opened cuts touch (vertex_split.h)
};

// Preconditions: `closed` is what close_handles returned on `mesh`, nothing added since.
// Each part that close_handles took to genus 0 and whose farthest cap stands beyond `near`
// (over the part's diagonal) loses its caps when the part's faces without them are one piece
// that, once a vertex where two cuts' holes touch is split per fan (split then in the mesh
// too), is an open sphere that can be cut into a disc (can_become_disc, open_part_cuts.h) or
// falls apart into such open spheres; otherwise it keeps them. The faces after a removed cap move
// down in order; no vertex moves or goes (a split appends copies), so a vertex only caps used (a
// later cycle ran across an earlier cap) is left without faces: the caller drops it
// (drop_unused_vertices, weld.h). O(faces + corners). `stop` may be null.
HandleOpening open_far_handles(PolygonMesh& mesh, const HandleClosing& closed, double near,
                               const StopCheck* stop = nullptr);

}  // namespace spheremap
