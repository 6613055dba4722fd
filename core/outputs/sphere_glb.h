// The spherical mesh written as a GLB, and checked as written.
#pragma once

#include <array>
#include <span>

#include "core/io/glb_writer.h"
#include "core/io/gltf_appearance.h"
#include "core/map/map_check.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// A spherical mesh as a GLB (normals = positions, Draco when draco_position_bits > 0),
// and the verdict on the map as written: the file decoded again by our own reader,
// positions float32 (and quantized, with Draco), checked like the map. Set extras in
// glb.json before serialize_glb(glb): they do not change what was checked.
struct WrittenGlb {
  GlbParts glb;
  MapCheck check;
};
// The input's look to keep (a glTF input in its own layout, without Draco): the sphere is
// then written as the input's scene (materials, attributes, nodes) with sphere positions.
struct SphereLook {
  const GltfAppearance* appearance = nullptr;  // null: a plain GLB
  const PolygonMesh* input = nullptr;          // the mesh read with `appearance`
  std::vector<char> skip_face;                 // input faces not in `sphere` (empty: none)
};
// `without_fills`: `sphere` lacks faces the map has (holes filled before mapping, which the
// input's layout does not show), so its signed areas fall short of 4 pi by theirs: the
// check as written then asks for no fold and no degenerate triangle only (the map itself
// was checked whole, in double and float32).
// `colors` (plain GLB only, may be empty): COLOR_0, one per vertex of `sphere`.
WrittenGlb sphere_glb(const PolygonMesh& sphere, bool inward, int draco_position_bits,
                      const SphereLook& look = {}, bool without_fills = false,
                      std::span<const std::array<float, 3>> colors = {});

}  // namespace spheremap
