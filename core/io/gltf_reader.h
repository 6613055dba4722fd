// Reading glTF 2.0 (GLB, or JSON with its buffers embedded or supplied by a
// GltfResources), plain, KHR_draco_mesh_compression, KHR_mesh_quantization or
// EXT_meshopt_compression, as one polygon mesh of triangles; glTF 1.0 too, through its 2.0
// upgrade (gltf1_upgrade.h). Input is untrusted: nothing
// here touches the filesystem or the network itself (external URIs go to the caller's
// GltfResources, checked first), every index, offset, stride and count is checked
// against the bytes actually present before it is used, and sizes are capped. Errors are
// InputError("gltf", message) with our own messages only; "missing_resources" when
// named files were not supplied. EXT_mesh_gpu_instancing's instances are read as copies
// in world space, at most 256 in all ("instancing" past that, with the fix of mapping the
// mesh once).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "core/io/gltf_appearance.h"
#include "core/io/gltf_resources.h"
#include "core/mesh/mesh.h"
#include "core/mesh/topology.h"

namespace spheremap {

struct GltfReadOptions {
  // >= 0: only this mesh, with the transform of the first node that draws it (identity
  // when none does), not the scene.
  int mesh_index = -1;
  std::string mesh_name;  // non-empty: only the mesh of this name
  // Over either cap: InputError("too_large") (the service answers 413).
  size_t max_vertices = 20'000'000;
  size_t max_triangles = 40'000'000;
  // Bytes of buffers and images held in all (data: URIs decoded, files supplied, images
  // copied out), each distinct source counted once however many references name it;
  // over it: InputError("too_large").
  size_t max_resource_bytes = size_t{4} << 30;
  // Asked every few thousand elements while reading: true stops the read with
  // InputError("stopped") (an intake deadline passed, the process is shutting down).
  std::function<bool()> should_stop;
};

// What was read, for reports: primitives used and skipped (points, lines).
struct GltfReadStats {
  size_t primitives = 0, skipped_primitives = 0, draco_primitives = 0;
  // The mesh the scene draws most often when some mesh is drawn by several nodes.
  int repeated_mesh = -1;
  size_t repeated_mesh_draws = 0;
  // Every mesh drawn, in drawing order (first draw), with the triangles it added.
  struct DrawnMesh {
    size_t index = 0, triangles = 0;
    std::string name;
  };
  std::vector<DrawnMesh> drawn_meshes;
  // Departures from the spec that were read anyway (byteStride 0), one sentence per kind.
  std::vector<std::string> warnings;
};

// Every TRIANGLES (and strip/fan, converted) primitive of the default scene with node
// transforms applied (world space), or of the chosen mesh. Vertices are not welded:
// glTF splits them along seams; weld() joins them. With `appearance`, also what the
// outputs carry over (materials, textures, attributes, nodes), aligned with the mesh.
PolygonMesh read_gltf(std::span<const uint8_t> bytes, const GltfReadOptions& options = {},
                      GltfReadStats* stats = nullptr, const GltfResources* resources = nullptr,
                      GltfAppearance* appearance = nullptr);

// Fixes that the glTF scene suggests for the topology failures that several meshes cause
// (non-manifold edges where copies overlap, several components where they do not): a mesh
// drawn several times is to be mapped alone (--mesh / the job option mesh); a scene of
// several meshes gets them listed (index, name, triangles) in the first failure's message.
void suggest_gltf_fixes(std::vector<ValidationFailure>& failures, const GltfReadStats& stats);

}  // namespace spheremap
