// The envelope's surface made good (Reach II, step 3): the voxel surface smoothed, and
// after its reduction (envelope_reduce.h) every vertex moved toward the offset surface of
// the original (its closest point on the original plus the offset, outward) and smoothed
// again, each move rejected when it would turn an incident triangle by more than 60
// degrees or make it degenerate (so nothing folds). Moves change no connectivity.
#pragma once

#include <cstddef>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {

// Taubin's lambda|mu smoothing (no shrinkage), `iterations` pairs; moves that fold are
// skipped. Triangle meshes only.
void smooth_surface(PolygonMesh& mesh, int iterations, StopCheck& stop);

// `iterations` rounds of: each vertex toward closest(original) + offset along the way out,
// then one smoothing step; both without folding. Returns the vertices moved in the last
// round. The closest-point queries run on `threads` (0: all cores); the result does not
// depend on it.
size_t fit_to_offset(PolygonMesh& mesh, const TriangleTree& original, double offset, int iterations,
                     int threads, StopCheck& stop);

}  // namespace spheremap
