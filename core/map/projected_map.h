// The paper's map of one mesh (ALGORITHM §A2-§A3) as a building block: projection about
// the weighted centroid, orientation by majority, Lai-Cheng smoothing until 0 folds (after
// the minimum iterations) or a budget, then local repair. Used on the whole mesh first
// (smooth, star-shaped shapes map at once: igea in 10 iterations) and on coarse levels
// as the start of the coarse-to-fine chain.
#pragma once

#include <span>
#include <vector>

#include "core/map/map_session.h"
#include "core/map/repair.h"
#include "core/mesh/sparse_matrix.h"

namespace spheremap {

struct ProjectedMap {
  std::vector<Vec3> sphere;
  size_t iterations = 0;
  RepairStats repair;
  size_t folds = 0;  // left at the end; the map is usable only when 0
};

struct ProjectedMapBudget {
  size_t iterations = 1000;
  bool repair = true;
  // Give up once `probe_iterations` are done and more than this share of the
  // triangles is still folded (a projection that folds that much rarely recovers).
  size_t probe_iterations = 0;  // 0: never give up early
  double max_fold_share = 1.0;
};

ProjectedMap projected_map(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                           SparseMatrix A, const SmoothingOptions& smoothing,
                           const ProjectedMapBudget& budget, const MapSession& session,
                           MapProgress progress);

// Mirrors q if most triangles are negatively oriented (ALGORITHM §B1).
void orient_by_majority(std::vector<Vec3>& q, std::span<const Triangle> triangles);

}  // namespace spheremap
