// Splitting non-manifold vertices (Reach I, cleaning): a vertex whose faces form several
// fans (edge-connected around it: two cones touching at their tips, a surface pinched to a
// point) becomes one vertex per fan, each at the same position. No vertex moves and no
// face is added or dropped. Done on the welded mesh: the weld would merge the copies again.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/prepare/edge_pairing.h"

namespace spheremap {

struct VertexSplit {
  size_t vertices_split = 0;  // vertices of several fans
  size_t vertices_added = 0;  // the copies: one per fan after the first
};

// Each vertex's faces are grouped into fans (two faces share a fan when they share an edge
// at the vertex); the fan of its first corner (in face order) keeps the vertex, each other
// fan gets a copy appended after the mesh's vertices. Faces using a vertex twice count
// once per corner. With `pairs` (edge_pairing.h), two faces at a paired edge share a fan
// only when they are partners there. O(corners log degree). `stop` may be null.
VertexSplit split_non_manifold_vertices(PolygonMesh& mesh, const StopCheck* stop = nullptr,
                                        const EdgePairs* pairs = nullptr);

}  // namespace spheremap
