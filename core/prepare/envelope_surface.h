// The envelope's first surface (Reach II, step 3): the boundary of the union of the ball's
// closed voxel cubes, two triangles per boundary face, facing out. The ball is
// well-composed (envelope_topology.h), so no edge or corner of the grid is shared by two
// sheets: the surface is a closed 2-manifold, a sphere when the ball is one.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"
#include "core/prepare/envelope_grid.h"

namespace spheremap {

// Vertices at grid corners (each once), triangles only. Precondition: no ball voxel on the
// grid's border.
PolygonMesh voxel_surface(const VoxelGrid& grid, const std::vector<uint8_t>& ball, StopCheck& stop);

}  // namespace spheremap
