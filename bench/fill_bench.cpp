// fill_bench: what refining and fairing hole fills (core/prepare/fill_refinement.h) and
// weighing them down in the map's energy (MapOptions::filled_weight) do, on one mesh with
// holes. Per setting (least-area fill, weight 1 — the old behaviour; refined and faired,
// weight 1; refined and faired, weight 0.1 — the default; and weight 0.01): the stretch
// and area distortion of the input's OWN faces only, whether the map is certified, and
// the 256 x 256 octahedral remesh's distance to the input's own faces (each direction, over
// its diagonal) and to the filled surface; and the seconds.
//
//   fill_bench MESH [MAX_HOLE_FILL]   (default 0.05)
//
// One JSON line per setting. Exit 2 on unreadable input.
#include <chrono>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/map/certification.h"
#include "core/map/metrics.h"
#include "core/map/pipeline.h"
#include "core/mesh/surface_distance.h"
#include "core/outputs/remesh.h"

namespace {

using namespace spheremap;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

nlohmann::json run(const PolygonMesh& input, double max_hole_fill, bool refine, double weight) {
  PolygonMesh copy = input;
  PrepareOptions prepare;
  prepare.max_hole_fill = max_hole_fill;
  prepare.refine_hole_fills = refine;
  const auto start = Clock::now();
  const PreparedMesh prepared = prepare_input(copy, nullptr, prepare);
  const double prepare_seconds = seconds_since(start);
  nlohmann::json row = {{"refine", refine},
                        {"filled_weight", weight},
                        {"holes_filled", prepared.preparation.holes_filled},
                        {"holes_left", prepared.preparation.holes_left},
                        {"faces_added", prepared.preparation.faces_added},
                        {"vertices_added", prepared.preparation.vertices_added},
                        {"prepare_seconds", prepare_seconds}};
  if (!remaining_failures(prepared).empty() || prepared.topology.component_vertices.size() != 1) {
    row["skipped"] = "not one part that maps";
    return row;
  }
  MapOptions options;
  options.filled_weight = weight;
  const auto map_start = Clock::now();
  const MappedMesh mapped = map_prepared(prepared, options);
  row["map_seconds"] = seconds_since(map_start);
  row["certified"] = certify(mapped, mapped.float32_check).certified;
  const PolygonMesh& mesh = prepared.welded.mesh;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  // One part: the welded faces are the input's, then the fills (each a triangle).
  const size_t own_faces = mesh.face_count() - prepared.preparation.faces_added;
  size_t own_triangles = 0;
  for (size_t f = 0; f < own_faces; ++f) own_triangles += mesh.face_size(f) - 2;
  const std::span<const Triangle> own(oriented.triangles.data(), own_triangles);
  const QualityMetrics own_quality = compute_metrics(mesh.positions, mapped.map.sphere, own);
  row["own_stretch_l2"] = own_quality.stretch_l2;
  row["own_area_mean_abs_log"] = own_quality.area_log_ratio.mean;
  row["all_stretch_l2"] = mapped.quality.stretch_l2;
  if (mapped.map.check.bijective) {
    const OctahedralRemesh remesh =
        octahedral_remesh(mesh.positions, mapped.map.sphere, oriented.triangles, 256);
    const SurfaceDistance to_own =
        surface_distance(mesh.positions, own, remesh.positions, remesh.triangles);
    const SurfaceDistance to_filled =
        surface_distance(mesh.positions, oriented.triangles, remesh.positions, remesh.triangles);
    row["remesh_vs_own_hausdorff"] = to_own.hausdorff;
    row["own_to_remesh_max"] = to_own.max_a_to_b;
    row["own_to_remesh_rms"] = to_own.rms_a_to_b;
    row["remesh_vs_filled_hausdorff"] = to_filled.hausdorff;
    row["remesh_vs_filled_rms"] = to_filled.rms;
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: fill_bench MESH [MAX_HOLE_FILL]\n");
    return 2;
  }
  try {
    const PolygonMesh input = read_mesh_file(argv[1]);
    const double max_hole_fill = argc == 3 ? std::stod(argv[2]) : 0.05;
    const struct {
      bool refine;
      double weight;
    } settings[] = {{false, 1.0}, {true, 1.0}, {true, 0.1}, {true, 0.01}};
    for (const auto& s : settings) {
      nlohmann::json row = run(input, max_hole_fill, s.refine, s.weight);
      row["mesh"] = argv[1];
      std::printf("%s\n", row.dump().c_str());
      std::fflush(stdout);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fill_bench: %s\n", e.what());
    return 2;
  }
}
