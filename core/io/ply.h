// PLY (Stanford polygon format), ASCII and binary (little and big endian): positions from
// the `vertex` element's x, y, z (any numeric type, any order), polygons from the `face`
// element's `vertex_indices` (or `vertex_index`) list. Every other element and property
// (normals, colours, texture coordinates, lists) is skipped by its size.
#pragma once

#include <string_view>

#include "core/io/mesh_limits.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// Throws InputError("parse") with counts on a malformed header, declared counts that the
// bytes cannot hold (checked before allocating), a truncated body, an index out of range,
// a face of fewer than 3 corners, or non-finite coordinates; InputError("too_large") when
// the declared vertex or face count, or the triangles read, are over `limits`, the counts
// before anything is allocated.
PolygonMesh parse_ply(std::string_view bytes, const MeshLimits& limits = {});

}  // namespace spheremap
