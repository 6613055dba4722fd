#include "core/pipeline.h"

#include <chrono>

namespace spheremap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

PreparedMesh prepare_mesh(const PolygonMesh& input, const PrepareOptions& options) {
  PreparedMesh prepared;
  prepared.welded = weld(input, options.weld_tolerance);
  prepared.topology = analyze_topology(prepared.welded.mesh);
  return prepared;
}

MappedMesh map_mesh(const PolygonMesh& input, const PrepareOptions& prepare,
                    const MapOptions& options, const MapControl& control) {
  MappedMesh out;
  auto start = std::chrono::steady_clock::now();
  out.prepared = prepare_mesh(input, prepare);
  require_mappable(out.prepared.topology);
  out.prepare_seconds = seconds_since(start);

  out.map = map_to_sphere(out.prepared.welded.mesh, options, control);
  if (out.map.sphere.empty()) return out;  // cancelled

  start = std::chrono::steady_clock::now();
  const PolygonMesh& mesh = out.prepared.welded.mesh;
  out.quality = compute_metrics(mesh.positions, out.map.sphere, oriented_triangles(mesh).triangles);
  out.metrics_seconds = seconds_since(start);
  return out;
}

PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped) {
  PolygonMesh out = input;
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  for (size_t v = 0; v < out.positions.size(); ++v)
    out.positions[v] = to_welded[v] == kUnreferenced ? Vec3{} : mapped.map.sphere[to_welded[v]];
  return out;
}

}  // namespace spheremap
