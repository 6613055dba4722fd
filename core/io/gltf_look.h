// Copying a glTF document's look (materials, textures, images, cameras, nodes) into a
// GltfAppearance, checked so that a writer can reuse every index as it is. Internal to
// the glTF reader.
#pragma once

#include <string>
#include <vector>

#include "core/io/gltf_appearance.h"
#include "core/io/gltf_document.h"

namespace spheremap::gltf {

// Fills everything but primitives and attributes. `roots`: the default scene's nodes;
// `visited`: per node, whether the scene walk reached it (only those are copied; the
// others stay as empty objects so indices hold). Materials whose texture references do
// not resolve are dropped with the textures (primitives then have none).
void copy_scene_look(const Document& doc, const std::vector<size_t>& roots,
                     const std::string& scene_name, const std::vector<char>& visited,
                     GltfAppearance& look);

}  // namespace spheremap::gltf
