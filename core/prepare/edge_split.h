// Splitting non-manifold edges where closed surfaces meet (Reach II, fidelity): two solids
// that share an edge (a tetrahedron in a cube's corner, welded at the corners; kitbashed
// boxes sharing a rim) are one component with edges of four faces, which no part maps and
// an envelope of the whole loses the inner solid of. Each such edge is split between the
// surfaces when every surface uses it exactly twice (closed there), so each maps as a part
// of its own. No vertex moves and no face is added or dropped. Done on the welded mesh.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct EdgeSplit {
  size_t edges_split = 0;     // non-manifold edges shared out between surfaces
  size_t vertices_added = 0;  // copies of the vertices the surfaces shared
};

// Faces are grouped into sheets: joined across every edge of exactly two faces, and across
// a non-manifold edge unless each sheet there has exactly two of its faces (then the edge
// is split; otherwise, a fin or an odd fan, its sheets are joined, until none is left
// unsplittable). Each vertex's first corner's sheet keeps it; every other sheet at the
// vertex gets a copy appended after the mesh's vertices. A mesh without non-manifold edges
// is unchanged. O(corners log corners) per pass, at most one pass per join. `stop` may be
// null.
EdgeSplit split_non_manifold_edges(PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
