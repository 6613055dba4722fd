#include "core/map/pipeline.h"

#include <algorithm>
#include <chrono>

#include "core/mesh/sphere_geometry.h"
#include "core/mesh/union_find.h"

namespace spheremap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

namespace {

// Drops every face outside the largest component (by faces) and the vertices left unused.
void keep_largest_component(WeldResult& welded) {
  PolygonMesh& mesh = welded.mesh;
  UnionFind sets(mesh.vertex_count());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  std::vector<size_t> faces_of(mesh.vertex_count(), 0);
  for (size_t f = 0; f < mesh.face_count(); ++f) ++faces_of[sets.find(mesh.face(f)[0])];
  const uint32_t keep =
      static_cast<uint32_t>(std::max_element(faces_of.begin(), faces_of.end()) - faces_of.begin());
  PolygonMesh kept;
  std::vector<uint32_t> new_id(mesh.vertex_count(), kUnreferenced);
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (sets.find(mesh.face(f)[0]) != keep) continue;
    corners.clear();
    for (uint32_t v : mesh.face(f)) {
      if (new_id[v] == kUnreferenced) {
        new_id[v] = static_cast<uint32_t>(kept.positions.size());
        kept.positions.push_back(mesh.positions[v]);
      }
      corners.push_back(new_id[v]);
    }
    kept.add_face(corners);
  }
  for (uint32_t& w : welded.input_to_welded)
    if (w != kUnreferenced) w = new_id[w];
  mesh = std::move(kept);
}

}  // namespace

PreparedMesh prepare_mesh(const PolygonMesh& input, const PrepareOptions& options) {
  PreparedMesh prepared;
  StopCheck stop(&options.should_stop);
  prepared.welded = weld(input, options.weld_tolerance, &stop);
  stop.check();
  if (options.largest_component) keep_largest_component(prepared.welded);
  stop.check();
  prepared.topology = analyze_topology(prepared.welded.mesh, &stop);
  return prepared;
}

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
  require_mappable(prepared.topology);
  MappedMesh out;
  out.prepared = std::move(prepared);
  out.map = map_to_sphere(out.prepared.welded.mesh, options, control);
  if (out.map.sphere.empty()) return out;  // cancelled

  const auto start = std::chrono::steady_clock::now();
  const PolygonMesh& mesh = out.prepared.welded.mesh;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  // The metrics are ratios that do not depend on placement or units; their sums of areas
  // would (overflow at 1e200, underflow at 1e-200), so they are taken on the mesh
  // centred and scaled.
  out.quality =
      compute_metrics(centered_and_scaled(mesh.positions), out.map.sphere, oriented.triangles);
  out.float32_check =
      verify_map(rounded_to_float32(out.map.sphere), oriented.triangles, mesh, oriented.inward);
  out.metrics_seconds = seconds_since(start);
  return out;
}

PolygonMesh sphere_on_input(const PolygonMesh& input, const MappedMesh& mapped) {
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  PolygonMesh out;
  out.positions.resize(input.vertex_count());
  for (size_t v = 0; v < out.positions.size(); ++v)
    out.positions[v] = to_welded[v] == kUnreferenced ? Vec3{} : mapped.map.sphere[to_welded[v]];
  for (size_t f = 0; f < input.face_count(); ++f)
    if (to_welded[input.face(f)[0]] != kUnreferenced) out.add_face(input.face(f));
  return out;
}

PolygonMesh sphere_welded(const MappedMesh& mapped) {
  PolygonMesh out = mapped.prepared.welded.mesh;
  out.positions = mapped.map.sphere;
  return out;
}

}  // namespace spheremap
