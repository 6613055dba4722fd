// Reading and writing meshes by file extension: .obj, .off, .glb, .gltf in; .obj, .glb out.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/io/gltf_reader.h"
#include "core/mesh.h"

namespace spheremap {

// Throws InputError("io") for unreadable files or unknown extensions, and
// InputError("parse") for malformed content.
PolygonMesh read_mesh_file(const std::string& path, const GltfReadOptions& gltf = {});
// GLB output is fan-triangulated, with `extras` on its mesh; sphere_normals writes each
// position as its normal (right for a mesh on the unit sphere).
void write_mesh_file(const std::string& path, const PolygonMesh& mesh,
                     const nlohmann::json& extras = nlohmann::json::object(),
                     bool sphere_normals = false);

}  // namespace spheremap
