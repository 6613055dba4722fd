// The sphere of an asset of several parts: each part's own unit sphere in a node of its
// own that moves it to where the part is (MappedPart::center, radius). The positions stay
// on the unit sphere in the file (float32 and Draco keep their precision whatever the
// asset's size), and the check as written reads the file back with the nodes unmoved.
#include <algorithm>

#include "core/io/gltf_reader.h"
#include "core/map/certification.h"
#include "core/mesh/sphere_geometry.h"
#include "core/mesh/submesh.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"

namespace spheremap {
namespace {

// Part k's spherical mesh in `layout`: its welded vertices, or its input vertices in first
// use order (seams of the input kept) with its input faces `faces`. `local`: submesh's
// scratch, shared by the parts so that all parts together cost O(input).
PolygonMesh part_sphere(const PolygonMesh& input, const MappedMesh& mapped, size_t k,
                        SphereLayout layout, const PartIndex& index,
                        const std::vector<uint32_t>& faces, std::vector<uint32_t>& local) {
  const MappedPart& part = mapped.parts[k];
  // A wrapped part (prepare auto) has no input faces: its envelope is what it shows.
  if (layout == SphereLayout::kWelded || faces.empty()) {
    PolygonMesh out = part.mapped.prepared.welded.mesh;
    out.positions = part.mapped.map.sphere;
    return out;
  }
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  MeshPart faces_part = submesh(input, faces, &local);
  PolygonMesh& out = faces_part.mesh;
  for (uint32_t v = 0; v < out.vertex_count(); ++v)
    out.positions[v] = part.mapped.map.sphere[index.local[to_welded[faces_part.vertex[v]]]];
  // The same faces named by the part's welded vertices.
  PolygonMesh welded_ids;
  welded_ids.offsets = out.offsets;
  welded_ids.indices.reserve(out.indices.size());
  for (uint32_t c : out.indices)
    welded_ids.indices.push_back(index.local[to_welded[faces_part.vertex[c]]]);
  // The corner first whose fan the part's map was certified on (pipeline.h).
  return apex_first(out, welded_ids);
}

// The file's meshes read back (nodes unmoved, so on their unit spheres) and each part's
// triangles checked on its own sphere.
MapCheck check_as_written(const GlbParts& unmoved, const MappedMesh& mapped,
                          const std::vector<size_t>& part_triangles, bool without_fills) {
  const std::string bytes = serialize_glb(unmoved);
  const PolygonMesh decoded =
      read_gltf({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
  std::vector<Triangle> triangles = fan_triangulate(decoded).triangles;
  std::vector<Vec3> directions(decoded.positions.size());
  for (size_t v = 0; v < directions.size(); ++v)
    directions[v] = normalized_or(decoded.positions[v], Vec3{});
  MapCheck total;
  total.min_signed_area = INFINITY;
  total.bijective = true;
  size_t first = 0, expected = 0;
  for (size_t k = 0; k < mapped.parts.size(); ++k) expected += part_triangles[k];
  if (triangles.size() != expected) {
    total.bijective = false;
    return total;
  }
  for (size_t k = 0; k < mapped.parts.size(); ++k) {
    std::span<Triangle> part(triangles.data() + first, part_triangles[k]);
    if (mapped.parts[k].mapped.map.inward)
      for (Triangle& t : part) std::swap(t[1], t[2]);
    MapCheck check = check_map(directions, part);
    // Holes filled before mapping are not in the input's layout (sphere_glb.h).
    if (without_fills) check.bijective = check.folds == 0;
    add_check(total, check);
    first += part_triangles[k];
  }
  return total;
}

}  // namespace

SphereAsset parts_sphere_asset(const PolygonMesh& input, const MappedMesh& mapped,
                               const MapOptions& options, SphereLayout layout,
                               int draco_position_bits, const GltfAppearance* appearance) {
  const PartIndex index(mapped);
  const std::vector<const PartReport*> reports = part_reports(mapped);
  DecodedImages decoded;  // each base-colour image decoded once for all parts
  // Each part's input faces, in one pass.
  std::vector<std::vector<uint32_t>> faces_of(mapped.parts.size());
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  if (layout == SphereLayout::kOriginal)
    for (size_t f = 0; f < input.face_count(); ++f)
      if (const uint32_t w = to_welded[input.face(f)[0]]; w != kUnreferenced)
        faces_of[index.part[w]].push_back(static_cast<uint32_t>(f));
  std::vector<uint32_t> local(layout == SphereLayout::kOriginal ? input.vertex_count() : 0,
                              kUnreferenced);
  std::vector<GlbMesh> meshes(mapped.parts.size());
  std::vector<size_t> part_triangles;
  std::vector<GlbNode> unmoved(mapped.parts.size()), placed(mapped.parts.size());
  for (size_t k = 0; k < mapped.parts.size(); ++k) {
    const PolygonMesh sphere = part_sphere(input, mapped, k, layout, index, faces_of[k], local);
    meshes[k].positions = meshes[k].normals = sphere.positions;
    meshes[k].triangles = fan_triangulate(sphere).triangles;
    // A wrapped part shows its envelope (welded vertices): coloured from its faces.
    const std::vector<Vec3>& surface = mapped.parts[k].mapped.prepared.welded.mesh.positions;
    if (reports[k] && reports[k]->wrapped && surface.size() == sphere.positions.size()) {
      const OriginalSurface original =
          original_surface(input, appearance, &reports[k]->original_faces);
      if (auto colors =
              colors_closest(original, surface, options.smoothing.threads, nullptr, &decoded))
        meshes[k].colors = std::move(*colors);
    }
    part_triangles.push_back(meshes[k].triangles.size());
    unmoved[k].name = placed[k].name = "part " + std::to_string(k);
    placed[k].translation = mapped.parts[k].center;
    placed[k].scale = mapped.parts[k].radius > 0 ? mapped.parts[k].radius : 1;
  }
  const bool without_fills =
      layout == SphereLayout::kOriginal && mapped.prepared.preparation.faces_added > 0;
  auto write = [&](int bits) {
    for (GlbMesh& mesh : meshes) mesh.draco_position_bits = bits;
    GlbParts glb = build_glb(meshes, unmoved);
    return std::pair{glb, check_as_written(glb, mapped, part_triangles, without_fills)};
  };
  std::pair<GlbParts, MapCheck> file;
  if (draco_position_bits == kDracoBitsAutomatic) {
    for (const int bits : kDracoAutomaticBits) {
      file = write(bits);
      draco_position_bits = bits;
      if (clean(file.second) || !clean(mapped.float32_check)) break;
    }
  } else {
    file = write(draco_position_bits);
  }
  auto& [glb, written] = file;
  for (size_t k = 0; k < placed.size(); ++k) {
    nlohmann::json& node = glb.json["nodes"][k];
    node["translation"] = {placed[k].translation.x, placed[k].translation.y,
                           placed[k].translation.z};
    node["scale"] = {placed[k].scale, placed[k].scale, placed[k].scale};
  }
  SphereAsset asset;
  asset.written = written;
  asset.metrics = metrics_json(mapped, options);
  const Certification verdict = certify(mapped, written);
  asset.metrics["bijective"] = verdict.certified;
  if (!verdict.certified)
    asset.metrics["problem"] = {{"type", verdict.problem}, {"detail", verdict.detail}};
  asset.metrics["bijective_as_written"] = clean(written);
  asset.metrics["folds_as_written"] = written.folds;
  asset.metrics["kept_appearance"] = false;
  if (draco_position_bits != 0) asset.metrics["draco_position_bits"] = draco_position_bits;
  if (std::any_of(meshes.begin(), meshes.end(), [](const GlbMesh& m) { return !m.colors.empty(); }))
    asset.metrics["vertex_colors"] =
        "COLOR_0 on wrapped parts: the original's base colour at the closest point";
  glb.json["meshes"][0]["extras"] = without_timings(asset.metrics);
  asset.glb = serialize_glb(glb);
  return asset;
}

}  // namespace spheremap
