#include "core/outputs/sphere_asset.h"

#include "core/map/certification.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/original_surface.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_glb.h"

namespace spheremap {

PolygonMesh sphere_mesh(const PolygonMesh& input, const MappedMesh& mapped, SphereLayout layout) {
  return layout == SphereLayout::kWelded ? sphere_welded(mapped) : sphere_on_input(input, mapped);
}

std::vector<char> dropped_faces(const PolygonMesh& input, const MappedMesh& mapped) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  std::vector<char> dropped(input.face_count(), 0);
  for (size_t f = 0; f < input.face_count(); ++f)
    dropped[f] = to_welded[input.face(f)[0]] == kUnreferenced;
  return dropped;
}

std::vector<uint32_t> welded_input_faces(const PolygonMesh& input, const MappedMesh& mapped) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < input.face_count(); ++f)
    if (to_welded[input.face(f)[0]] != kUnreferenced) faces.push_back(f);
  return faces;
}

SphereAsset sphere_asset(const PolygonMesh& input, const MappedMesh& mapped,
                         const MapOptions& options, SphereLayout layout, int draco_position_bits,
                         const GltfAppearance* appearance) {
  if (!mapped.parts.empty())
    return parts_sphere_asset(input, mapped, options, layout, draco_position_bits, appearance);
  SphereLook look;
  if (appearance && !appearance->empty() && layout == SphereLayout::kOriginal &&
      draco_position_bits == 0)
    look = {appearance, &input, dropped_faces(input, mapped)};
  const PolygonMesh sphere = sphere_mesh(input, mapped, layout);
  const bool without_fills =
      layout == SphereLayout::kOriginal && mapped.prepared.preparation.faces_added > 0;
  // An envelope's sphere takes the original's base colour per vertex (COLOR_0), from the
  // closest point of the original to the envelope's vertex.
  std::vector<std::array<float, 3>> colors;
  if (!look.appearance)
    if (const std::optional<OriginalSurface> original = wrapped_original(mapped)) {
      const std::vector<Vec3>& surface =
          layout == SphereLayout::kWelded ? mapped.prepared.welded.mesh.positions : input.positions;
      if (surface.size() == sphere.positions.size())
        if (auto c = colors_closest(*original, surface, options.smoothing.threads, nullptr))
          colors = std::move(*c);
    }
  WrittenGlb file;
  if (draco_position_bits == kDracoBitsAutomatic) {
    for (const int bits : kDracoAutomaticBits) {
      file = sphere_glb(sphere, mapped.map.inward, bits, look, without_fills, colors);
      draco_position_bits = bits;
      // More bits cannot help a map that is not certified in float32 already.
      if (clean(file.check) || !clean(mapped.float32_check)) break;
    }
  } else {
    file = sphere_glb(sphere, mapped.map.inward, draco_position_bits, look, without_fills, colors);
  }
  SphereAsset asset;
  asset.written = file.check;
  asset.metrics = metrics_json(mapped, options);
  const Certification verdict = certify(mapped, file.check);
  asset.metrics["bijective"] = verdict.certified;
  if (!verdict.certified)
    asset.metrics["problem"] = {{"type", verdict.problem}, {"detail", verdict.detail}};
  asset.metrics["bijective_as_written"] = clean(file.check);
  asset.metrics["folds_as_written"] = file.check.folds;
  if (draco_position_bits != 0) asset.metrics["draco_position_bits"] = draco_position_bits;
  if (!colors.empty())
    asset.metrics["vertex_colors"] = "COLOR_0: the original's base colour at the closest point";
  file.glb.json["meshes"][0]["extras"] = without_timings(asset.metrics);
  asset.glb = serialize_glb(file.glb);
  return asset;
}

}  // namespace spheremap
