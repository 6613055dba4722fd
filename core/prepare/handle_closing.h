// Closing handles exactly (Reach I): a closed, manifold, oriented part of genus g > 0 (a
// ring, a handle, a plate with through-holes) is cut along a short non-separating cycle and
// both sides of the cut are closed with the least-area fill of hole_filling.h; g cuts make
// it genus 0. As Praun & Hoppe's MinCycles: the cycles are those of a tree-cotree homotopy
// basis (Erickson & Whittlesey's greedy: a shortest-path tree from a root, a dual spanning
// tree of the other edges by decreasing loop length, each leftover edge closing one cycle),
// from a few roots, shortest first, recomputed after each cut.
//
// A cut copies the cycle's vertices (appended after the mesh's own, same positions): the
// faces on one side use the copies. The fills are appended after the mesh's faces, like
// hole fills, so outputs that show only the original leave them out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

// The most handles one part may have to be closed (each costs a few shortest-path trees
// over the part, about a microsecond per face): at most kMaxHandles, and at most
// kHandleWork / faces (a part of a million faces: 16). A part of higher genus is left as
// it is.
inline constexpr size_t kMaxHandles = 256;
inline constexpr size_t kHandleWork = size_t{1} << 24;

struct HandleClosing {
  size_t handles_closed = 0, faces_added = 0;
  size_t handles_left = 0;   // genus left in the parts that were closed, manifold and oriented
  double largest_cycle = 0;  // the longest cycle cut, over its part's bounding-box diagonal
  // The farthest any cut's fill strays from its part's own faces, over the part's diagonal.
  double farthest_fill = 0;
  // Per vertex added (mesh.vertex_count() before closing + k): the vertex it copies (one
  // of the mesh's own).
  std::vector<uint32_t> copy_of;
  // Per part still of genus > 0: one of its vertices and what stopped the closing, with
  // the numbers ("the shortest non-separating cycle left is 0.8 of ...").
  struct Stopped {
    uint32_t vertex = 0;
    size_t genus = 0;
    std::string reason;
  };
  std::vector<Stopped> stopped;
  // Per part cut (to genus 0 or not): its fills, the mesh's faces [first_fill, first_fill +
  // fills) (a part's cuts append them in a row), and the farthest over its diagonal.
  struct ClosedPart {
    size_t first_fill = 0, fills = 0, cuts = 0;
    double farthest = 0;
    bool genus_left = false;  // some of its handles could not be closed
  };
  std::vector<ClosedPart> closed_parts;
};

// Preconditions: `mesh` welded (one vertex per point). Parts (connected components) that
// are not closed, manifold (edges and vertices) and consistently oriented, or of genus 0,
// are untouched. In the others, handles are closed while the next cycle is at most
// `max_cycle` times the part's bounding-box diagonal long and the part's genus is at most
// `max_genus` and kHandleWork / its faces; a cycle is cut only when it is simple, leaves the part
// connected (non- separating) and both its sides can be filled without a non-manifold edge, a crack
// triangle (kCrackArea) or more than kMaxHoleCorners corners. Of the 16 shortest distinct
// cycles, those whose fill lies within 1% of the part's diagonal of its own faces (those
// below `own_faces`: not earlier fills) are tried first, shortest first, then the others,
// nearest fill first; when a part's farthest fill still stands beyond 1%, it is closed
// again shortest first and the closing whose farthest fill is nearer is kept. `stop` may be
// null.
HandleClosing close_handles(PolygonMesh& mesh, double max_cycle, const StopCheck* stop = nullptr,
                            size_t max_genus = kMaxHandles, size_t own_faces = SIZE_MAX);

}  // namespace spheremap
