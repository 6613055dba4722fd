// Reading and writing meshes by file extension (.obj, .off).
#pragma once

#include <string>

#include "core/mesh.h"

namespace spheremap {

// Throws InputError("io") for unreadable files or unknown extensions, and
// InputError("parse") for malformed content.
PolygonMesh read_mesh_file(const std::string& path);
void write_mesh_file(const std::string& path, const PolygonMesh& mesh);

}  // namespace spheremap
