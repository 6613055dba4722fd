// Reading meshes by file extension (.obj, .off, .stl, .ply, .drc, .glb, .gltf; any case);
// writing OBJ.
#pragma once

#include <stdexcept>
#include <string>

#include "core/io/gltf_reader.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// Throws InputError("io") for unreadable files or unknown extensions, and
// InputError("parse") for malformed content. A .gltf's buffers named by relative URI are
// read from the .gltf's own folder (see gltf_resources.h); `stats` as read_gltf's.
PolygonMesh read_mesh_file(const std::string& path, const GltfReadOptions& gltf = {},
                           GltfReadStats* stats = nullptr, GltfAppearance* appearance = nullptr);
// OBJ only (GLB output goes through sphere_glb, which checks the file it writes).
void write_mesh_file(const std::string& path, const PolygonMesh& mesh);

// A file that cannot be written: the output's fault (a folder that does not exist, no
// permission, a full disk), never the input's, so not an InputError.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes bytes (a GLB, a JSON report) to path; OutputError, with the system's reason,
// when it cannot.
void write_binary_file(const std::string& path, const std::string& bytes);

}  // namespace spheremap
