// Draco bytes of a mesh, written by the tests with Draco's own encoder: the raw .drc reader
// and the service's .drc intake are tested on what draco_encoder would write.
#pragma once

#include <draco/compression/encode.h>
#include <draco/point_cloud/point_cloud.h>

#include <string>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap::testing {

// Gives `out` one point per position and a float32 POSITION attribute holding them.
void add_draco_positions(draco::PointCloud& out, const std::vector<Vec3>& positions);

// The .drc of the triangle mesh (positions unquantized). Precondition: every face is a
// triangle. Throws std::runtime_error when Draco refuses to encode it.
std::string drc_bytes(const PolygonMesh& mesh,
                      draco::MeshEncoderMethod method = draco::MESH_SEQUENTIAL_ENCODING);

// The .drc of a point cloud of `positions` (no faces). Throws std::runtime_error when Draco
// refuses to encode it.
std::string drc_point_cloud_bytes(const std::vector<Vec3>& positions);

}  // namespace spheremap::testing
