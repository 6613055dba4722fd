// glTF 1.0 read by rewriting its JSON as the glTF 2.0 JSON of the same geometry, which the
// 2.0 reader then checks and reads like any other file. Internal to the glTF reader.
//
// Why a rewrite and not a second reader: 1.0 and 2.0 store geometry alike (buffers,
// views, typed accessors, a node tree with matrices or TRS); they differ in how things are
// named (1.0 objects are dictionaries keyed by string ids, 2.0 ones arrays), where an
// accessor's stride lives (1.0: the accessor; 2.0: its bufferView) and how materials are
// described (1.0: shader techniques with parameter values; 2.0: PBR factors). That is
// what Cesium's gltf-pipeline does to upgrade a file, and what this does, for what
// spheremap reads: geometry, node transforms and the diffuse colour or texture.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>

#include "core/mesh/input_error.h"

namespace spheremap::gltf {

// True when `json`'s asset.version says 1.x (as a string "1", "1.x", or a number in [1, 2):
// some exporters wrote it as a number).
bool declares_gltf1(const nlohmann::json& json);

// The GLB 1.0 container (KHR_binary_glTF): a 20-byte header (magic, version 1, length,
// content length, content format 0 = JSON), the JSON content, then the binary body.
// `json_text` and `body` are set to the two parts; fails (InputError "gltf") when the
// header's lengths do not fit the bytes or the content is not JSON.
void split_glb1(std::span<const uint8_t> bytes, std::span<const uint8_t>* json_text,
                std::span<const uint8_t>* body);

// The glTF 2.0 document that reads as `v1` does. Precondition: declares_gltf1(v1).
//   has_body: the file is a GLB 1.0 with a binary body; the buffer KHR_binary_glTF names
//             "binary_glTF" becomes buffer 0 without a uri, the 2.0 GLB's BIN chunk.
// Kept: buffers, bufferViews, accessors (each with a bufferView of its own that carries its
// byteStride), meshes (a primitive's attributes POSITION, NORMAL, TEXCOORD_n, COLOR_n;
// its indices, material and mode), nodes (children, matrix or TRS; a node of several
// meshes gets one child node per mesh), scenes, the default scene, samplers, images (by
// uri or KHR_binary_glTF bufferView), textures, and each material's diffuse colour or
// texture (its values, or KHR_materials_common's) as base colour. CESIUM_RTC's centre is
// added as a root translation. Dropped: techniques and their shaders, animations, skins,
// cameras, lights. Refused: WEB3D_quantized_attributes (positions need its decode matrix).
// A reference to an id the file does not have fails, naming both.
nlohmann::json upgrade_gltf1(const nlohmann::json& v1, bool has_body);

// `e` raised while reading an upgraded file: a "gltf" error gets a note that its indices
// (bufferView 2, mesh 0) number the upgrade's objects, in the order of the 1.0 ids; other
// checks (missing_resources, too_large) name files and sizes and are returned as they are.
InputError in_upgrade(const InputError& e);

}  // namespace spheremap::gltf
