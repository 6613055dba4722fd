// Writing a mesh with the look of the glTF it was read from: the input's materials,
// textures, images, attributes (TEXCOORD_n, COLOR_0), names, node hierarchy and
// transforms, with new positions (the sphere, or the mesh with a morph target onto it).
#pragma once

#include <vector>

#include "core/io/glb_writer.h"
#include "core/io/gltf_appearance.h"
#include "core/mesh/mesh.h"

namespace spheremap {

struct SceneGeometry {
  // The mesh read_gltf() returned with `look` (its faces; positions are not used).
  const PolygonMesh* input = nullptr;
  // World space, one per input vertex, as read_gltf() returns positions.
  std::vector<Vec3> positions;
  // Unit world-space normals per input vertex, or empty to keep the input's NORMAL.
  std::vector<Vec3> normals;
  // Faces to leave out (components dropped before mapping); empty: none.
  std::vector<char> skip_face;
  // A morph target: world-space positions and unit normals the mesh morphs to (empty:
  // none), and the seconds of an animation playing 0 -> 1 -> 0 (0: none).
  std::vector<Vec3> morph_positions, morph_normals;
  double morph_seconds = 0;
};

// One glTF mesh per drawing node, a primitive per input primitive with its material;
// positions written in each node's frame so that the scene shows `positions` in world
// space (a node whose transform cannot be inverted is moved to the scene's root). The
// first mesh carries `extras`. Precondition: !look.empty(), look and geometry.input
// come from the same read_gltf() call.
GlbParts build_scene_glb(const GltfAppearance& look, const SceneGeometry& geometry,
                         const nlohmann::json& extras);

}  // namespace spheremap
