#include "core/map/projected_map.h"

#include "core/map/projection.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {

void orient_by_majority(std::vector<Vec3>& q, std::span<const Triangle> triangles) {
  size_t negative = 0;
  for (const Triangle& t : triangles) negative += triple_product(q[t[0]], q[t[1]], q[t[2]]) < 0;
  if (2 * negative > triangles.size())
    for (Vec3& p : q) p.x = -p.x;
}

ProjectedMap projected_map(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                           SparseMatrix A, const SmoothingOptions& smoothing,
                           const ProjectedMapBudget& budget, const MapSession& session,
                           MapProgress progress) {
  const MapOptions& options = session.options();
  ProjectedMap out;
  out.sphere = project_to_sphere(positions, A, options.presmooth_steps, smoothing.threads);
  orient_by_majority(out.sphere, triangles);
  LaiChengSmoother smoother(triangles, std::move(A), positions.size(), smoothing);
  out.folds = smoother.count_folds(out.sphere);
  const double give_up = budget.max_fold_share * static_cast<double>(triangles.size());
  while (out.iterations < budget.iterations &&
         !(out.folds == 0 && out.iterations >= options.min_level_iterations) &&
         !session.should_stop()) {
    out.folds = smoother.step(out.sphere);
    ++out.iterations;
    progress.iteration = out.iterations, progress.folds = out.folds;
    session.report(progress);
    if (budget.probe_iterations && out.iterations == budget.probe_iterations &&
        static_cast<double>(out.folds) > give_up)
      return out;
  }
  if (out.folds > 0 && budget.repair) {
    out.repair = local_repair(smoother, out.sphere, out.folds, options.max_repair_iterations,
                              [&] { return session.should_stop(); });
    out.folds = out.repair.folds;
  }
  return out;
}

}  // namespace spheremap
