// Raw Draco files (.drc, what draco_encoder writes: Draco's own container, no glTF around
// it) as meshes.
#pragma once

#include <cstdint>
#include <span>

#include "core/io/mesh_limits.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// Whether the bytes start with Draco's magic "DRACO".
bool is_draco_file(std::span<const uint8_t> bytes);

// Inputs: the file's bytes; `limits`, capped further by the glTF reader's default caps
// (Draco allocates by the counts a stream declares, so they bound every read).
// Output: its triangles over its decoded points' positions (float32 as stored; other
// attributes, such as normals, colours and texture coordinates, are not read).
// The header's declared counts are checked before anything is decoded: over the caps,
// InputError("too_large"). A Draco point cloud: InputError("empty"), saying so. A stream
// that is not Draco bitstream 2.2, or is malformed or truncated: InputError("parse").
PolygonMesh read_draco_file(std::span<const uint8_t> bytes, const MeshLimits& limits = {});

}  // namespace spheremap
