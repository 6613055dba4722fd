#include "core/outputs/original_surface.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/mesh/surface_distance.h"

namespace spheremap {

OriginalSurface original_surface(const PolygonMesh& mesh, const GltfAppearance* look,
                                 const std::vector<uint32_t>* faces) {
  OriginalSurface out;
  out.mesh = &mesh;
  out.look = look;
  auto add = [&](uint32_t f) {
    const auto corners = mesh.face(f);
    for (size_t k = 1; k + 1 < corners.size(); ++k) {
      out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
      out.face.push_back(f);
    }
  };
  if (faces) {
    for (uint32_t f : *faces)
      if (f < mesh.face_count()) add(f);
  } else {
    for (size_t f = 0; f < mesh.face_count(); ++f) add(static_cast<uint32_t>(f));
  }
  return out;
}

std::optional<OriginalSurface> wrapped_original(const MappedMesh& mapped) {
  const auto& original = mapped.prepared.original;
  if (!original) return std::nullopt;
  return original_surface(original->mesh, &original->look);
}

nlohmann::json distance_to_original(const OriginalSurface& original,
                                    std::span<const Vec3> positions,
                                    std::span<const Triangle> triangles, int threads,
                                    const std::function<bool()>* should_stop) {
  const SurfaceDistance d = surface_distance(original.mesh->positions, original.triangles,
                                             positions, triangles, threads, should_stop);
  return {{"relative_to", "bounding-box diagonal of the original triangles"},
          {"diagonal", d.diagonal},
          {"rms", d.rms},
          {"hausdorff", d.hausdorff},
          {"hausdorff_at_most", d.hausdorff_at_most},
          {"hausdorff_settled", d.hausdorff_settled},
          {"original_to_output", {{"rms", d.rms_a_to_b}, {"max", d.max_a_to_b}}},
          {"output_to_original", {{"rms", d.rms_b_to_a}, {"max", d.max_b_to_a}}},
          {"original_triangles", original.triangles.size()},
          {"samples", d.samples}};
}

VertexDistances vertex_distances(const OriginalSurface& original, std::span<const Vec3> points,
                                 int threads, const std::function<bool()>* should_stop) {
  const auto start = std::chrono::steady_clock::now();
  const PointDistances d =
      point_distances(original.mesh->positions, original.triangles, points, threads, should_stop);
  VertexDistances out;
  double max = 0, sum2 = 0;
  for (double x : d.relative) {
    out.relative.push_back(static_cast<float>(x));
    max = std::max(max, x);
    sum2 += x * x;
  }
  const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
  out.metrics = {{"attribute", "_DISTANCE"},
                 {"relative_to", "bounding-box diagonal of the original triangles"},
                 {"diagonal", d.diagonal},
                 {"max", max},
                 {"rms", points.empty() ? 0.0 : std::sqrt(sum2 / points.size())},
                 {"vertices", points.size()},
                 {"seconds", seconds.count()}};
  return out;
}

}  // namespace spheremap
