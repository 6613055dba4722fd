// Copies of input vertices added by preparation (a handle cut puts a vertex of the input on
// both sides of the cut: a seam, as glTF makes them), keeping every per-vertex array of the
// input right: positions, faces, input_to_welded and a glTF look's attributes, whose
// primitives each own a contiguous vertex range.
#pragma once

#include <cstdint>
#include <vector>

#include "core/io/gltf_appearance.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// On entry `input`'s faces may use vertices input.vertex_count() + k, the copies of
// source[k] (not yet in `input`), and `input_to_welded` has an entry for each of them after
// the input's own. On return the copies are in `input` with source's positions and, in
// `look` (may be null), its attributes, each at the end of its source's primitive range
// (the ranges grow to hold them; the vertices after move up); faces and input_to_welded
// renumbered to match. Without a look the copies are appended.
void insert_vertex_copies(PolygonMesh& input, GltfAppearance* look,
                          const std::vector<uint32_t>& source,
                          std::vector<uint32_t>& input_to_welded);

}  // namespace spheremap
