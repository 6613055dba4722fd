// Reading glTF 2.0 (GLB, or JSON with embedded data: buffers), Draco-compressed or not,
// as one polygon mesh of triangles. Input is untrusted: nothing here touches the
// filesystem or the network (external URIs are refused), every index, offset, stride
// and count is checked against the bytes actually present before it is used, and sizes
// are capped. Errors are InputError("gltf", message) with our own messages only.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/mesh/mesh.h"

namespace spheremap {

struct GltfReadOptions {
  int mesh_index = -1;    // >= 0: only this mesh (identity transform), not the scene
  std::string mesh_name;  // non-empty: only the mesh of this name
  // Over either cap: InputError("too_large") (the service answers 413).
  size_t max_vertices = 20'000'000;
  size_t max_triangles = 40'000'000;
};

// What was read, for reports: primitives used and skipped (points, lines).
struct GltfReadStats {
  size_t primitives = 0, skipped_primitives = 0, draco_primitives = 0;
};

// Every TRIANGLES (and strip/fan, converted) primitive of the default scene with node
// transforms applied (world space), or of the chosen mesh. Vertices are not welded:
// glTF splits them along seams; weld() joins them.
PolygonMesh read_gltf(std::span<const uint8_t> bytes, const GltfReadOptions& options = {},
                      GltfReadStats* stats = nullptr);

}  // namespace spheremap
