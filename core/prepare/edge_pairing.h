// Non-manifold edges where a surface touches itself, paired by angle (Reach II, cleaning).
// A CAD solid whose features meet along an edge (a slot cut to a rib's edge, two bosses
// touching, a fillet closed to nothing) has edges of four faces, all of one connected
// surface, which edge_split.h cannot share out between surfaces: the part was wrapped (the
// iCub robot's CAD parts: 4-67 such edges each, their envelopes 3-6% of the diagonal off).
// Around such an edge the faces, sorted by angle, bound wedges of solid and of empty space
// in turn; each face is paired with the face across the solid wedge beside it, so the solid
// is taken as touching itself there without being joined through the edge. The split is
// then made per vertex (vertex_split.h with the pairs): no vertex moves, no face is added.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/union_find.h"

namespace spheremap {

// One side of a face along an edge: the edge (undirected_edge_key, hole_filling.h), the
// face, the face's next corner after the edge (it spans the face's side), and whether the
// face runs the edge from its smaller vertex to its larger.
struct EdgeCorner {
  uint64_t edge;
  uint32_t face;
  uint32_t far;
  bool forward;
  bool operator<(const EdgeCorner& o) const {
    return edge != o.edge ? edge < o.edge : face < o.face;
  }
};

// Every face side of `mesh` (a side between a corner and itself left out), sorted by edge,
// then face. O(corners log corners). `stop` may be null.
std::vector<EdgeCorner> sorted_edge_corners(const PolygonMesh& mesh, const StopCheck* stop);

// The sheets of a mesh of `faces` faces whose sorted_edge_corners are `corners`: faces
// joined across each edge of exactly two faces (not across an edge of one or of more).
UnionFind manifold_sheets(std::span<const EdgeCorner> corners, uint32_t faces);

// Per non-manifold edge (undirected_edge_key, hole_filling.h) whose faces pair: each face
// with its partner, both ways.
using EdgePairs = std::unordered_map<uint64_t, std::vector<std::pair<uint32_t, uint32_t>>>;

// An edge pairs when it has 4 or more faces, each running along it once, as many each way,
// no two at the same angle about it (of their next corners) but two running opposite ways
// apart from the rest: faces of two solids stacked face to face (each keeps its own face
// on the plane they share), taken as an empty wedge of no width. A face running a -> b (a < b)
// has its solid on the side of smaller angles about a -> b, one running b -> a on the side
// of larger ones; read by angle, they match as closing and opening brackets (each pair
// bounds a solid wedge where the directions alternate; where faces pass through each
// other, the pairs nest). Other edges (an odd fan, a fin, faces lying on each other, a face
// of no width there) are left out. `other`: at an edge of four faces, each face matched
// with the other face running the other way instead (a second try where faces pass through
// each other and the first match left the edge joined); edges of more faces are left out.
// O(corners log corners). `stop` may be null.
EdgePairs pair_faces_at_non_manifold_edges(const PolygonMesh& mesh, bool other = false,
                                           const StopCheck* stop = nullptr);

// The last resort at the edges left non-manifold by every rule above and by sheet_ends.h
// (an odd fan, more faces running one way than the other: a scan's stray flap on its
// surface, a volume grid's inner faces): per edge of 3 faces or more (each running along
// it once, no two at the same angle), the faces that match as brackets, as above, paired,
// and each other face let go (paired with nothing: it gets a boundary there when its
// vertices' fans come apart). A flap standing in empty space lets go; the surface through
// the edge keeps it. No vertex moves, no face is added. O(corners log corners).
EdgePairs pair_faces_letting_go_of_the_rest(const PolygonMesh& mesh,
                                            const StopCheck* stop = nullptr);

// The angles (radians, in (-pi, pi]) about the edge a -> b of the points `far` (each a
// face's next corner after the edge), from a common axis across the edge; empty when the
// edge or a point's distance from its line is of no length.
std::vector<double> angles_about_edge(const PolygonMesh& mesh, uint32_t a, uint32_t b,
                                      std::span<const uint32_t> far);

// The face across `edge` from `face` when the edge is paired; `face` itself when it is
// not in `pairs` (every face there is joined, as at a manifold edge).
uint32_t paired_face(const EdgePairs& pairs, uint64_t edge, uint32_t face);

}  // namespace spheremap
