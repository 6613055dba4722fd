#include "core/map/pipeline.h"

#include <algorithm>
#include <chrono>

#include "core/map/map_parts.h"
#include "core/mesh/sphere_geometry.h"
#include "core/mesh/submesh.h"

namespace spheremap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

MappedMesh map_mesh(const PolygonMesh& input, const PrepareOptions& prepare,
                    const MapOptions& options, const MapControl& control) {
  const auto start = std::chrono::steady_clock::now();
  PreparedMesh prepared = prepare_mesh(input, prepare);
  const double prepare_seconds = seconds_since(start);
  MappedMesh out = map_prepared(std::move(prepared), options, control);
  out.prepare_seconds = prepare_seconds;
  return out;
}

MappedMesh map_prepared(PreparedMesh prepared, const MapOptions& options,
                        const MapControl& control) {
  require_none(remaining_failures(prepared));
  if (prepared.topology.component_vertices.size() > 1)
    return map_parts(std::move(prepared), options, control);
  MappedMesh out;
  out.prepared = std::move(prepared);
  out.map = map_to_sphere(out.prepared.welded.mesh, options, control, out.prepared.filled);
  if (out.map.sphere.empty()) return out;  // cancelled
  measure_map(out, options);
  return out;
}

void measure_map(MappedMesh& out, const MapOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const PolygonMesh& mesh = out.prepared.welded.mesh;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  // The metrics are ratios that do not depend on placement or units; their sums of areas
  // would (overflow at 1e200, underflow at 1e-200), so they are taken on the mesh
  // centred and scaled.
  // Of the input's own faces: the faces preparation added (hole fills, handle caps) are
  // weighed down in the map and squeezed on purpose; their distortion is not the input's.
  const std::vector<char> filled = filled_mask(oriented.triangles, out.prepared.filled);
  double share = 4 * M_PI;
  for (size_t k = 0; k < filled.size(); ++k)
    if (filled[k]) {
      const Triangle& t = oriented.triangles[k];
      share -= spherical_area(out.map.sphere[t[0]], out.map.sphere[t[1]], out.map.sphere[t[2]]);
    }
  out.quality =
      compute_metrics(centered_and_scaled(mesh.positions), out.map.sphere,
                      kept_triangles(oriented.triangles, filled), options.smoothing.threads, share);
  out.float32_check =
      verify_map(rounded_to_float32(out.map.sphere), oriented.triangles, mesh, oriented.inward);
  out.metrics_seconds = seconds_since(start);
}

namespace {

// Per welded vertex, its sphere point; for an asset of several parts, moved to where its
// part's sphere is drawn (map_parts.h).
std::vector<Vec3> drawn_sphere(const MappedMesh& mapped) {
  std::vector<Vec3> sphere = mapped.map.sphere;
  for (const MappedPart& part : mapped.parts)
    for (uint32_t w : part.whole_vertex) sphere[w] = placed(part, sphere[w]);
  return sphere;
}

}  // namespace

PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  const std::vector<Vec3> sphere = drawn_sphere(mapped);
  PolygonMesh out;
  out.positions.resize(input.vertex_count());
  for (size_t v = 0; v < out.positions.size(); ++v)
    out.positions[v] = to_welded[v] == kUnreferenced ? Vec3{} : sphere[to_welded[v]];
  // The faces with the corner first whose fan the map was certified on (decided on the
  // faces over welded ids; the input's seams could pick another apex). Triangles have one.
  const bool polygons = !input.is_triangle_mesh();
  PolygonMesh welded_ids;
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < input.face_count(); ++f)
    if (to_welded[input.face(f)[0]] != kUnreferenced) {
      out.add_face(input.face(f));
      if (!polygons) continue;
      corners.clear();
      for (uint32_t v : input.face(f)) corners.push_back(to_welded[v]);
      welded_ids.add_face(corners);
    }
  if (!polygons) return out;
  welded_ids.positions.resize(mapped.prepared.welded.mesh.vertex_count());
  return apex_first(out, welded_ids);
}

PolygonMesh sphere_welded(const MappedMesh& mapped) {
  PolygonMesh out = mapped.prepared.welded.mesh;
  out.positions = drawn_sphere(mapped);
  return out;
}

}  // namespace spheremap
