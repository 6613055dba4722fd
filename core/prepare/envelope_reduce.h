// The envelope's reduction (Reach II, step 3): least quadric error first (Garland and
// Heckbert: corners and creases of the offset surface stay where they are), each edge
// collapsed to its point of least error only when the link condition holds (the two ends share
// exactly the two vertices opposite the edge, so the surface stays a 2-manifold of the same genus),
// no vertex is left with fewer than 3 neighbours, and no triangle around it turns by more than 60
// degrees. meshoptimizer's simplifier was tried first: it does not test the link condition and made
// non-manifold edges on most envelopes.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

// Precondition: a closed 2-manifold triangle mesh. Collapses until at most target_faces
// triangles remain or no edge may collapse; vertices left unused are dropped.
PolygonMesh reduce_surface(const PolygonMesh& mesh, size_t target_faces, StopCheck& stop);

}  // namespace spheremap
