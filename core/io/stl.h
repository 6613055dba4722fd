// STL (stereolithography), binary and ASCII: a list of triangles, each with its own three
// corners (no shared vertices). The mesh read has 3 vertices per triangle, in file order;
// the weld of prepare_mesh joins equal positions, so a closed STL maps like any mesh.
// Facet normals are ignored (orientation comes from the corner order).
#pragma once

#include <string_view>

#include "core/io/mesh_limits.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// Binary when the 80-byte header and the uint32 triangle count match the size exactly
// (84 + 50 * count bytes): binary files may begin with "solid" too. Otherwise ASCII,
// which must begin with "solid".
bool is_binary_stl(std::string_view bytes);

// Throws InputError("parse") with counts (binary) or the line number (ASCII) on malformed
// input, and on non-finite coordinates (with how many). A declared count that the bytes
// cannot hold is refused before anything is allocated, and so is one over
// limits.max_triangles (InputError("too_large")). max_vertices is not applied: an STL has
// 3 per triangle until welded.
PolygonMesh parse_stl(std::string_view bytes, const MeshLimits& limits = {});

}  // namespace spheremap
