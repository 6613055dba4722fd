// Open parts cut into discs (Reach II, prepare=auto): a part that is a sphere with several
// holes (an open tube or pipe, a sleeve, a lampshade, a garment, a scan with gaps: genus 0,
// b >= 2 boundary loops) whose holes are left open becomes a disc when cut along b - 1
// paths that join its loops, and a disc is closed exactly by its own back
// (sheet_doubling.h), where filling such holes sets caps as far from the part as the holes
// are wide, and wrapping it moves every point by the envelope's offset.
//
// Each path is the shortest, along edges, from the loops joined so far to another loop
// (Prim's order over the loops, Dijkstra from all the joined loops' vertices at once), so
// the seams are short and the doubled part's two sides meet along few edges. A cut gives
// each path vertex a copy for the faces on the path's left (a seam, as glTF makes them: the
// copy stays where the vertex was), so no point moves and no face is added; the map then
// puts the seam's two sides apart on the sphere, as it does a sheet's boundary.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/topology.h"

namespace spheremap {

// Past this many boundary loops a part is left (each join costs a pass over the part, and
// kMaxCutWork bounds them all: a CAD part of 38 through-holes opened has 76).
inline constexpr size_t kMaxJoinedLoops = 256;
// Joins x corners at most, for one part (each join rebuilds the part's half-edges and
// searches it: ~0.05 us a corner here, so about 3 s): a larger part is left (wrapped).
inline constexpr size_t kMaxCutWork = size_t{1} << 26;

// Whether a part with this topology (analyze_topology of the part alone) and this many
// corners is one cut_open_parts_into_discs cuts, or a disc: an open sphere of at most
// kMaxJoinedLoops holes, (loops - 1) x corners within kMaxCutWork.
bool can_become_disc(const TopologyReport& topology, size_t corners);

struct OpenPartCuts {
  size_t parts_cut = 0;       // parts made discs
  size_t paths_cut = 0;       // paths cut, one per loop joined
  size_t vertices_added = 0;  // the paths' copies, appended after the mesh's vertices
};

// Preconditions: `mesh` welded (one vertex per point). Every connected component that is
// an open sphere with 2 to kMaxJoinedLoops boundary loops, and (loops - 1) x corners within
// kMaxCutWork, is cut into a disc (checked: a
// part whose cut would not be one is left as it was). Faces keep their order and sizes, only
// corners on the paths' left renamed to the copies. O(loops x corners log corners) per
// part. `stop` may be null.
OpenPartCuts cut_open_parts_into_discs(PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
