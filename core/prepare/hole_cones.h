// Holes closed for a while by cones (Reach II, prepare=auto). A part with holes left open
// and handles too (a scan of a statue with an open base and holes through it; a room's
// shell with its doorways and an open side) is neither a closed part whose handles
// handle_closing.h cuts, nor an open sphere that open_part_cuts.h cuts into a disc, so it
// was wrapped: the envelope's membranes over the doorways stood up to 0.89 model units
// (11% of a scene's diagonal) from the room. Each of its holes is closed by a cone (a
// vertex at the loop's centroid, a triangle per edge) so that handle_closing.h sees a
// closed part and cuts its handles; the cones are then taken out again, and what is left is
// an open sphere, cut into a disc and closed by its own back like any other. No point of
// the input moves: the cones only lend the handle search a closed surface.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct HoleCones {
  size_t first_face = 0, faces = 0;  // the cones' triangles: mesh faces [first, first + faces)
  size_t parts = 0, loops = 0;       // parts coned, loops closed
};

// Preconditions: `mesh` welded (one vertex per point). Each connected part (faces joined
// across edges) that has boundary loops, genus > 0 (from its Euler characteristic and loop
// count), no edge of more than two faces, consistently oriented edges and simple loops (no
// vertex on two boundary edges running out of it) gets a cone in every loop: a vertex at the
// loop's centroid appended after the mesh's vertices, a triangle (b, a, apex) per boundary
// edge a -> b (the way its face runs it) appended after its faces. Other parts are left as
// they are. O(corners log corners). `stop` may be null.
HoleCones cone_holes_of_parts_with_handles(PolygonMesh& mesh, const StopCheck* stop = nullptr);

}  // namespace spheremap
