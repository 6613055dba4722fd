// Lai & Cheng's loop as published (ALGORITHM §A2-§A3), with the §B3 decisions: unsigned
// areas in the centroid move, and the offset placement given by the options.
#include <algorithm>

#include "core/limit_operator.h"
#include "core/map_session.h"
#include "core/projected_map.h"
#include "core/projection.h"
#include "core/sphere_geometry.h"

namespace spheremap {

void map_paper(const PolygonMesh& mesh, std::span<const Triangle> triangles,
               const MapSession& session, MapResult& result) {
  const MapOptions& options = session.options();
  SparseMatrix A = limit_operator(mesh, options.alpha);
  std::vector<Vec3> q =
      project_to_sphere(mesh.positions, A, options.presmooth_steps, options.smoothing.threads);

  orient_by_majority(q, triangles);

  LaiChengSmoother smoother(triangles, std::move(A), q.size(), options.smoothing);
  size_t folds = smoother.count_folds(q);
  const auto stage = [&](size_t it) {
    session.report({.stage = "smooth",
                    .level = 1,
                    .levels = 1,
                    .vertices = q.size(),
                    .iteration = it,
                    .folds = folds});
  };
  stage(0);
  size_t it = 0;
  while (!(folds == 0 && it >= options.min_level_iterations)) {
    if (it >= options.max_iterations) {
      result.stop_reason = StopReason::kIterationLimit;
      break;
    }
    if (session.should_stop()) {
      result.stop_reason = session.stop_reason();
      break;
    }
    folds = smoother.step(q);
    stage(++it);
  }
  result.iterations = it;
  result.fine_iteration_equivalents = static_cast<double>(it);
  result.levels.push_back({.vertices = q.size(), .iterations = it, .folds = folds});
  result.mapping_seconds = session.elapsed();
  if (result.stop_reason != StopReason::kCancelled) result.sphere = std::move(q);
}

}  // namespace spheremap
