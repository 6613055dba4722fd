// The spherical mesh written as a GLB, and checked as written.
#pragma once

#include "core/io/glb_writer.h"
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
WrittenGlb sphere_glb(const PolygonMesh& sphere, bool inward, int draco_position_bits);

}  // namespace spheremap
