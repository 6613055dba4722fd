// The original surface a wrapped output stands for (prepare wrap, or auto wrapping the
// whole or a part): the input's faces an envelope replaced, as triangles of the input's
// own vertices, with the input's look. The outputs of an envelope measure their distance
// to it and bake its base colour from it by closest point (base_color_bake.h).
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/io/gltf_appearance.h"
#include "core/map/pipeline.h"
#include "core/mesh/mesh.h"

namespace spheremap {

struct OriginalSurface {
  const PolygonMesh* mesh = nullptr;     // the input before wrapping; must outlive this
  const GltfAppearance* look = nullptr;  // its look (may be empty); must outlive this
  std::vector<Triangle> triangles;       // fan triangles of its faces, on mesh's vertices
  std::vector<uint32_t> face;            // per triangle, its face of `mesh`
};

// The faces `faces` of `mesh` (every face when `faces` is null), with `look` (may be null).
OriginalSurface original_surface(const PolygonMesh& mesh, const GltfAppearance* look,
                                 const std::vector<uint32_t>* faces = nullptr);

// What a mapped mesh of one part stands for when it is an envelope of the whole input
// (mapped.prepared.original); nothing otherwise (its input then is the original).
std::optional<OriginalSurface> wrapped_original(const MappedMesh& mapped);

// The two-sided distance (core/mesh/surface_distance) between the triangles `positions,
// triangles` of an output and `original`, relative to the original's bounding-box
// diagonal, as the metrics' "distance_to_original" object.
nlohmann::json distance_to_original(const OriginalSurface& original,
                                    std::span<const Vec3> positions,
                                    std::span<const Triangle> triangles, int threads,
                                    const std::function<bool()>* should_stop);

// Per point of an envelope (its vertices, in the original's units), the distance to the
// closest point of `original` (one query each, core/mesh/surface_distance), relative to
// the original's bounding-box diagonal as distance_to_original: the `_DISTANCE` vertex
// attribute of a wrapped morph, which the page draws as a heat map. `metrics`: the
// attribute's name, its max and RMS, the diagonal and the seconds taken.
// `should_stop` (may be null) is asked every 4096 points; true throws InputError("stopped").
struct VertexDistances {
  std::vector<float> relative;  // one per point
  nlohmann::json metrics;
};
VertexDistances vertex_distances(const OriginalSurface& original, std::span<const Vec3> points,
                                 int threads, const std::function<bool()>* should_stop);

}  // namespace spheremap
