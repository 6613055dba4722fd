// Writing a triangle mesh as a self-contained GLB (glTF 2.0 binary): float32 POSITION
// (with the min/max glTF requires), optional NORMAL, TANGENT, TEXCOORD_0, COLOR_0 and
// _DISTANCE,
// uint32 indices, one node, `extras` on the mesh (our metrics); optionally a textured
// material (base colour, normal map), a morph target and its animation.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

struct GlbMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // empty, or one per position
  std::vector<Triangle> triangles;
  nlohmann::json extras = nlohmann::json::object();
  // > 0: compress with KHR_draco_mesh_compression (marked required), positions quantized
  // to this many bits (normals to 10), sequential encoding so vertex order is kept.
  // Not with the members below.
  int draco_position_bits = 0;

  std::vector<std::array<float, 2>> texcoords;  // TEXCOORD_0: empty, or one per position
  std::string base_color_png;                   // non-empty: a material with this texture
  // Non-empty: the material's normalTexture (tangent space, linear RGB), with `tangents`
  // (TANGENT: xyz unit, w = +-1) one per position.
  std::string normal_png;
  std::vector<std::array<float, 4>> tangents;
  // COLOR_0 (linear RGB in [0, 1]): empty, or one per position. Draco encodes it too.
  std::vector<std::array<float, 3>> colors;
  // `_DISTANCE` (float SCALAR, an application-specific attribute glTF allows): empty, or
  // one per position; a wrapped morph's distance of each vertex to the original. Not
  // with Draco.
  std::vector<float> distances;
  std::string material_name = "checker";
  // One morph target: a displacement per position (and per normal, when given), the mesh's
  // weight 0; with morph_seconds > 0, an animation plays the weight 0 -> 1 -> 0 over it.
  std::vector<Vec3> morph_positions, morph_normals;
  double morph_seconds = 0;
};

// A GLB as its JSON and binary chunk: built once (encoding, Draco), serialized after the
// JSON is changed if need be (extras do not touch the binary data).
struct GlbParts {
  nlohmann::json json;
  std::string bin;
};
GlbParts build_glb(const GlbMesh& mesh);

// Where a mesh is drawn: a node of its own, scaled about the origin then moved.
struct GlbNode {
  std::string name;  // empty: none
  Vec3 translation;
  double scale = 1;
};
// Several meshes, each in its node (meshes[k] in nodes[k], all in the one scene); meshes
// with the same texture share one material, and every mesh with a morph animation plays
// in one animation (of the last such mesh's length).
GlbParts build_glb(std::span<const GlbMesh> meshes, std::span<const GlbNode> nodes);
std::string serialize_glb(const GlbParts& parts);
inline std::string format_glb(const GlbMesh& mesh) {
  return serialize_glb(build_glb(mesh));
}

// The same asset as glTF JSON text, its buffer embedded as a base64 data: URI. The JSON
// and binary chunks are the ones serialize_glb writes (a GLB of another writer may have
// others, which are dropped). Throws std::invalid_argument when `glb` is not a GLB.
std::string serialize_gltf(const GlbParts& parts);
std::string glb_to_gltf(std::string_view glb);

class GlbBuilder;
// The animation "mesh to sphere": each node's morph weight 0 -> 1 -> 0 over `seconds`.
nlohmann::json morph_animation(GlbBuilder& builder, double seconds,
                               const std::vector<size_t>& nodes);

}  // namespace spheremap
