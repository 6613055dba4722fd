// What users build on a map (ALGORITHM §E), each as a finished GLB with its metrics in
// the mesh's extras: the octahedral remesh (and its geometry image), the original
// surface with texture coordinates and a checker texture, and the mesh-to-sphere morph.
// Shared by `spheremap remesh|uv|morph` and the service's artifacts.
#pragma once

#include <functional>

#include <nlohmann/json.hpp>
#include <string>

#include "core/io/gltf_appearance.h"
#include "core/map/pipeline.h"

namespace spheremap {

struct RemeshAsset {
  std::string glb;
  std::string geometry_image_png;  // (N+1)^2 16-bit RGB; decode with metrics.geometry_image
  nlohmann::json metrics;          // sizes, closed/genus check, distance to the original
};

// Precondition: mapped.map.check.bijective. resolution: quads per side, even, >= 2.
// With the `appearance` read beside `input` (a glTF with materials or vertex colours),
// the GLB's material carries the input's base colour resampled onto the grid.
// `should_stop` (may be null: never stop) is asked between stages, between image
// decodes and every row of the colour bake; when it says true, remesh_asset throws
// InputError("stopped") within a row's time (a job's time limit or cancel).
// `normal_map`: the remesh of an envelope also carries the original's shading as a
// tangent-space normal map (normal_bake.h; about as long as the colour bake).
RemeshAsset remesh_asset(const MappedMesh& mapped, int resolution, int threads = 0,
                         const PolygonMesh* input = nullptr,
                         const GltfAppearance* appearance = nullptr,
                         const std::function<bool()>* should_stop = nullptr,
                         bool normal_map = true);

struct UvAsset {
  std::string glb;
  nlohmann::json metrics;  // seams, flipped and degenerate UV triangles, stretch
};

// Precondition: mapped.map.check.bijective. An envelope (prepare wrap, or a part auto
// wrapped: its faces of `input`, whose look is `appearance`) carries the original's base
// colour per vertex as COLOR_0, from the closest point of the original.
UvAsset uv_asset(const MappedMesh& mapped, const PolygonMesh* input = nullptr,
                 const GltfAppearance* appearance = nullptr);

struct MorphAsset {
  std::string glb;
  nlohmann::json metrics;
};

// The welded surface with one morph target onto a sphere of the same area about its
// centroid, and an animation of `seconds` playing mesh -> sphere -> mesh. With the
// `appearance` read beside `input` (a glTF), the input's own vertices, materials,
// textures, attributes and nodes instead of the welded surface.
MorphAsset morph_asset(const MappedMesh& mapped, double seconds = 4,
                       const PolygonMesh* input = nullptr,
                       const GltfAppearance* appearance = nullptr);

// A checker of 8 x 8 squares coloured by position (red grows with u, green with v),
// `size` pixels square, as an 8-bit PNG.
std::string checker_png(int size = 512);

}  // namespace spheremap
