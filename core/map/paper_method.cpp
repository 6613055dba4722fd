// Lai & Cheng's loop as published (ALGORITHM §A2-§A3), with the §B3 decisions: unsigned
// areas in the centroid move, and the offset placement given by the options. It is the
// projected map with the paper's iteration cap and no repair.
#include "core/map/limit_operator.h"
#include "core/map/map_session.h"
#include "core/map/projected_map.h"

namespace spheremap {

void map_paper(const PolygonMesh& mesh, std::span<const Triangle> triangles,
               const MapSession& session, MapResult& result) {
  const MapOptions& options = session.options();
  ProjectedMap map = projected_map(
      mesh.positions, triangles, limit_operator(mesh, options.alpha), options.smoothing,
      {.iterations = options.max_iterations, .repair = false}, session,
      {.stage = "smooth", .level = 1, .levels = 1, .vertices = mesh.vertex_count()});
  const bool done = map.folds == 0 && map.iterations >= options.min_level_iterations;
  if (!done)
    result.stop_reason =
        session.should_stop() ? session.stop_reason() : StopReason::kIterationLimit;
  result.iterations = map.iterations;
  result.fine_iteration_equivalents = static_cast<double>(map.iterations);
  result.levels.push_back(
      {.vertices = mesh.vertex_count(), .iterations = map.iterations, .folds = map.folds});
  result.mapping_seconds = session.elapsed();
  if (result.stop_reason != StopReason::kCancelled) result.sphere = std::move(map.sphere);
}

}  // namespace spheremap
