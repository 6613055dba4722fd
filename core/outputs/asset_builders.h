// The pieces of each asset for one mapped part: its GLB mesh and metrics before they
// become a file. map_outputs.h writes one part as it is; parts_outputs.h puts the pieces
// of an asset of several parts side by side in one file.
#pragma once

#include <functional>

#include <nlohmann/json.hpp>
#include <vector>

#include "core/io/glb_writer.h"
#include "core/io/gltf_appearance.h"
#include "core/map/pipeline.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/octahedral_frame_choice.h"
#include "core/outputs/original_surface.h"
#include "core/outputs/remesh.h"
#include "core/outputs/sphere_alignment.h"
#include "core/outputs/sphere_asset.h"

namespace spheremap {

// A geometry image's 16-bit RGB pixels (side x side, row 0 at v = +1) and how to decode it.
struct GeometryImage {
  int side = 0;
  std::vector<uint16_t> rgb;
  nlohmann::json description;
};
GeometryImage geometry_image(const OctahedralRemesh& remesh);

struct BuiltAsset {
  GlbMesh glb;
  nlohmann::json metrics;
};

struct BuiltRemesh : BuiltAsset {
  GeometryImage image;
};
// The remesh of one part (preconditions of remesh_asset). With `original` (the part is an
// envelope standing for it): its distance to the original too, and the original's base
// colour baked by closest point instead of through `input` and `appearance`. `images`
// (may be null): decoded base-colour images shared with the other parts' bakes.
// `normal_map`: with `original`, also its shading as a tangent-space normal map.
// `texture_size`: the side of its baked textures; 0 for remesh_texture_size(resolution).
// `input_faces` (may be null): as bake_base_color's. `frame_trial_distance`: turned
// frames are tried when the unturned remesh stands farther than this from the part,
// relative to the part's diagonal (kFrameTrialDistance; a part of an asset passes the
// asset's threshold in its own terms, parts_outputs.cpp).
BuiltRemesh build_remesh(const MappedMesh& mapped, int resolution, int threads,
                         const PolygonMesh* input, const GltfAppearance* appearance,
                         const std::function<bool()>* should_stop = nullptr,
                         const OriginalSurface* original = nullptr, DecodedImages* images = nullptr,
                         bool normal_map = true, int texture_size = 0,
                         const std::vector<uint32_t>* input_faces = nullptr,
                         double frame_trial_distance = kFrameTrialDistance);

// The UV mesh of one part, without its texture. With `original` (the part is an envelope
// standing for it): COLOR_0, the original's base colour at each vertex's closest point.
BuiltAsset build_uv(const MappedMesh& mapped, const OriginalSurface* original = nullptr,
                    DecodedImages* images = nullptr);

struct BuiltMorph : BuiltAsset {
  std::vector<Vec3> normals;  // of the welded surface
  SphereAlignment aligned;    // the sphere end, turned
  Vec3 centroid;
  double radius = 0;
};
// The morph of one part as a plain mesh (the welded surface).
BuiltMorph build_morph(const MappedMesh& mapped, double seconds);

// Per welded vertex of an asset of several parts: its part and its vertex in that part
// (kUnreferenced for none).
struct PartIndex {
  std::vector<uint32_t> part, local;
  explicit PartIndex(const MappedMesh& mapped);
};

// Per mapped part, its report (map_parts pairs the mappable reports with the parts in
// order), or null for all when they do not pair up.
std::vector<const PartReport*> part_reports(const MappedMesh& mapped);

// The same assets for an asset of several parts (mapped.parts), one node per part.
RemeshAsset parts_remesh_asset(const MappedMesh& mapped, int resolution, int threads,
                               const PolygonMesh* input, const GltfAppearance* appearance,
                               const std::function<bool()>* should_stop = nullptr,
                               bool normal_map = true);
UvAsset parts_uv_asset(const MappedMesh& mapped, const PolygonMesh* input = nullptr,
                       const GltfAppearance* appearance = nullptr);
// A wrapped part's morph carries the colour of its faces of `input` (look `appearance`).
MorphAsset parts_morph_asset(const MappedMesh& mapped, double seconds,
                             const PolygonMesh* input = nullptr,
                             const GltfAppearance* appearance = nullptr);
// Each part's unit sphere in a node placed at the part (the input's look is not kept; a
// wrapped part carries the colour of its faces of `input`, whose look is `appearance`, as
// COLOR_0).
SphereAsset parts_sphere_asset(const PolygonMesh& input, const MappedMesh& mapped,
                               const MapOptions& options, SphereLayout layout,
                               int draco_position_bits, const GltfAppearance* appearance = nullptr);

}  // namespace spheremap
