// The original's shading baked onto the remesh of its envelope as a tangent-space normal
// map (glTF normalTexture): the envelope is smooth where the original had bumps, facets
// and creases, and the map gives them back in shading.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/map/pipeline.h"
#include "core/outputs/original_surface.h"
#include "core/outputs/remesh.h"

namespace spheremap {

// glTF TANGENT (xyz unit, w = +-1 the handedness) per remesh sample: the direction of
// increasing TEXCOORD_0 u made orthogonal to the sample's normal, with
// bitangent = cross(normal, tangent) * w pointing up in the texture (decreasing v), as
// glTF's MikkTSpace convention has it. `normals`: one unit normal per sample.
std::vector<std::array<float, 4>> remesh_tangents(const OctahedralRemesh& remesh,
                                                  std::span<const Vec3> normals);

// The original's shading normal at a point of one of its triangles: the input's NORMAL
// attribute where its primitive has one (turned by its node's transform), else the
// area-weighted face normals summed over the faces around each vertex position (corners
// at the same position share one, so seams of the texture do not show).
class ShadingNormals {
 public:
  explicit ShadingNormals(const OriginalSurface& original);
  // At the point of original.triangles[t] with weights `w` in its corners: unit length.
  Vec3 at(uint32_t t, const std::array<double, 3>& w) const;
  bool from_attribute() const { return from_attribute_; }

 private:
  const OriginalSurface& original_;
  std::vector<Vec3> normal_;  // per corner of original.triangles: 3 t + k
  bool from_attribute_ = false;
};

struct BakedNormals {
  std::string png;  // size x size, 8-bit RGB: (n + 1) / 2 in (tangent, bitangent, normal)
  int size = 0;
  size_t unlocated_texels = 0;  // texels whose sphere point no triangle held (flat)
  bool from_attribute = false;  // the original's NORMAL attribute, not computed normals
};

// Each texel of the square (the layout of bake_base_color_closest) is located on the
// envelope through the map, takes the original's shading normal at the closest point of
// the original's triangles, and writes it in the remesh's tangent frame there (the
// frame a viewer interpolates from the remesh triangle holding the texel: NORMAL
// `normals` and TANGENT `tangents` per sample). Nothing when `original` has no triangles.
// `oriented`: the envelope's oriented_triangles(); `locator` (may be null: one is built)
// of the map's sphere and `oriented`. `should_stop` (may be null) is asked every row of
// texels; true throws InputError("stopped").
std::optional<BakedNormals> bake_normals_closest(
    const OriginalSurface& original, const MappedMesh& mapped, std::span<const Triangle> oriented,
    const OctahedralRemesh& remesh, std::span<const Vec3> normals,
    std::span<const std::array<float, 4>> tangents, int size, int threads,
    const std::function<bool()>* should_stop, const SphereLocator* locator = nullptr);

}  // namespace spheremap
