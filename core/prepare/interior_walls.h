// Walls between two solids stored once (Reach II, cleaning). Kitbashed models stack boxes
// with the face between them stored once: each box is open there and the wall closes both,
// so the wall's rim edges have three faces (the wall's and one of each box's), which
// edge_split.h cannot share out (each sheet has one face there) and the part was wrapped
// (Kenney's FPS walls: 7% of their diagonal off). Such a wall is doubled: a copy facing the
// other way is appended, each box takes the wall or its copy (the one running its rim
// edges the other way round), and the split is made per vertex (vertex_split.h with the
// pairs). No vertex moves; the wall's faces are added once more.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct InteriorWalls {
  size_t walls = 0;        // sheets doubled so
  size_t faces_added = 0;  // their copies, appended after the mesh's faces
  size_t vertices_added = 0;
};

// A wall is a sheet (faces joined across edges of two faces) with no edge of one face, whose
// other edges each have three faces: its own, one running the same way as it and one the
// other way, of two other sheets. Each wall found is doubled and split off as above. A mesh
// without edges of three faces is unchanged. O(corners log corners). `stop` may be null.
InteriorWalls double_interior_walls(PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
