// Short non-separating cycles of a closed, oriented surface of genus g > 0, for closing its
// handles (handle_closing.h): the cycles of tree-cotree homotopy bases after Erickson &
// Whittlesey's greedy system of loops. From a root, a shortest-path tree T (edge lengths);
// over the edges not in T, a spanning tree C of the faces taken by decreasing loop length
// (the loop of edge uv: the tree path to u, uv, the tree path back from v); each of the 2g
// edges in neither closes a cycle that crosses no edge of C, so cutting along it leaves
// every face connected to every other: it is non-separating. Its two tree paths share
// their way from the root down to where they part; without that, the cycle is simple.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct HandleCycle {
  std::vector<uint32_t> vertices;  // in order along the cycle; the last joins the first
  double length = 0;               // the sum of its edges' lengths
};

// Preconditions: `faces` (indices into `mesh`) form one closed, manifold, consistently
// oriented surface. Returns the cycles of the bases rooted at up to `roots` vertices (the
// first of the part, then each time the vertex farthest from the previous root), shortest
// first; 2g per root. Costs `roots` shortest-path trees and sorts over the part's edges.
// `stop` may be null.
std::vector<HandleCycle> handle_cycles(const PolygonMesh& mesh, std::span<const uint32_t> faces,
                                       size_t roots, const StopCheck* stop);

}  // namespace spheremap
