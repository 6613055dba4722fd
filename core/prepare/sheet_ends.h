// Sheets that end on another surface, detached there (Reach II, cleaning). Architecture and
// kitbashed scenes stand single-sided sheets on each other: a wall's lower edge lies on the
// floor's surface, a fin stands on a closed box, a shelf's board ends on its side. Such an
// edge has the surface passing through (two faces of one sheet) and the sheet ending there
// (one face of another); edge_split.h shares an edge out only when every sheet has two
// faces there, so it joined them all, the part stayed non-manifold and was wrapped: a room
// of walls on a floor became one envelope whose membranes over its doorways stood 0.79
// model units (4.6% of the scene's diagonal) from the room (dream-apartment).
// Here the ending sheet lets go of the edge: it gets a boundary there, and the surface
// passing through keeps it as an ordinary edge. Open sheets are then cut and doubled
// (open_part_cuts.h, sheet_doubling.h) or their small holes filled, each part on its own.
#pragma once

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/prepare/edge_pairing.h"

namespace spheremap {

// Per non-manifold edge where at least one sheet (manifold_sheets, edge_pairing.h) has a
// single face and every other sheet exactly two: each two-face sheet's faces paired with
// each other, the single faces left alone (paired with nothing: split_non_manifold_vertices
// gives them their own copies of the edge's vertices). Edges where a sheet has three faces
// or more, or a face runs along the edge twice, are left out. O(corners log corners).
// `stop` may be null.
EdgePairs pair_sheets_ending_on_edges(const PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
