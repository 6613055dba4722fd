// What a glTF input looks like beyond its surface: materials, textures and their images,
// vertex attributes (TEXCOORD_n, COLOR_0, NORMAL), names, the node hierarchy and
// transforms. read_gltf() fills it beside the mesh it returns; the outputs built on the
// map (sphere, morph, textured remesh) carry it over, so a textured model keeps its look.
//
// Vertices and faces are those of the mesh read_gltf() returned: primitive p owns the
// input vertices [first_vertex, first_vertex + vertex_count) and faces
// [first_face, first_face + face_count), in reading order.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace spheremap {

using Matrix4 = std::array<double, 16>;  // column-major, as glTF

struct GltfAppearance {
  // The input's own arrays, copied: materials, textures, samplers and cameras (their
  // indices stay valid), and images without their data (see image_bytes).
  nlohmann::json materials = nlohmann::json::array();
  nlohmann::json textures = nlohmann::json::array();
  nlohmann::json samplers = nlohmann::json::array();
  nlohmann::json cameras = nlohmann::json::array();
  nlohmann::json images = nlohmann::json::array();  // name and mimeType only
  // Encoded bytes per distinct image source (a bufferView, a data: URI, a file), each read
  // once: images that name one source share its entry, and every output writes it once
  // (a file whose 480 images name one bufferView holds its bytes once, not 480 times).
  std::vector<std::string> image_data;
  // Per image, its entry in image_data, or kNoImageData when the file did not carry its
  // bytes (an external image not supplied, an unknown format): writers put a 1x1 grey
  // placeholder there.
  static constexpr size_t kNoImageData = SIZE_MAX;
  std::vector<size_t> image_source;
  // Extensions the copied arrays use (materials, textures): for extensionsUsed/Required.
  std::vector<std::string> extensions_used, extensions_required;

  // Nodes of the default scene, copied with name, children, camera and transform (matrix
  // or TRS); `mesh` dropped (the writer sets it for nodes in `primitives`). Empty when the
  // mesh was read without a scene (writers then use one node with the identity).
  nlohmann::json nodes = nlohmann::json::array();
  std::vector<size_t> scene_nodes;  // the scene's root nodes
  std::string scene_name;

  struct Primitive {
    int64_t node = -1;      // the drawing node, -1 when none (a mesh read on its own)
    int64_t material = -1;  // index in materials, -1 for none
    std::string mesh_name;  // the glTF mesh it belongs to
    uint32_t first_vertex = 0, vertex_count = 0;
    uint32_t first_face = 0, face_count = 0;
    Matrix4 world{};        // node-to-world transform applied to its positions
    bool mirrored = false;  // world has a negative determinant: faces were flipped on read
    std::vector<std::string> attributes;  // names of the attributes it has (below)
    bool has(const std::string& name) const {
      return std::find(attributes.begin(), attributes.end(), name) != attributes.end();
    }
  };
  std::vector<Primitive> primitives;

  // Vertex attributes other than POSITION, as stored (normalized integers scaled), one
  // value of `components` floats per input vertex, zeros for primitives that lack it.
  struct Attribute {
    std::string name;  // "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0"
    int components = 0;
    std::vector<float> values;
  };
  std::vector<Attribute> attributes;

  // The encoded bytes of image `image`, or nullptr when there are none.
  const std::string* image_bytes(size_t image) const {
    if (image >= image_source.size() || image_source[image] >= image_data.size()) return nullptr;
    return &image_data[image_source[image]];
  }

  const Attribute* attribute(const std::string& name) const {
    for (const Attribute& a : attributes)
      if (a.name == name) return &a;
    return nullptr;
  }
  bool empty() const { return primitives.empty(); }
};

}  // namespace spheremap
