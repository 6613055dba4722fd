// Writing a triangle mesh as a self-contained GLB (glTF 2.0 binary): float32 POSITION
// (with the min/max glTF requires) and optional NORMAL, uint32 indices, one node, and
// `extras` on the mesh (our metrics).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace spheremap {

struct GlbMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty, or one per position
  std::vector<Triangle> triangles;
  nlohmann::json extras = nlohmann::json::object();
  // > 0: compress with KHR_draco_mesh_compression (marked required), positions quantized
  // to this many bits (normals to 10), sequential encoding so vertex order is kept.
  int draco_position_bits = 0;
};

// A GLB as its JSON and binary chunk: built once (encoding, Draco), serialized after the
// JSON is changed if need be (extras do not touch the binary data).
struct GlbParts {
  nlohmann::json json;
  std::string bin;
};
GlbParts build_glb(const GlbMesh& mesh);
std::string serialize_glb(const GlbParts& parts);
inline std::string format_glb(const GlbMesh& mesh) {
  return serialize_glb(build_glb(mesh));
}

}  // namespace spheremap
