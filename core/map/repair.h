// Removing the last folds of a level (ALGORITHM §B4.4, recipe steps 3c and 3d).
#pragma once

#include <functional>
#include <span>

#include "core/map/lai_cheng.h"

namespace spheremap {

struct RepairStats {
  size_t iterations = 0;
  double vertex_updates = 0;  // sum over iterations of the active vertex count
  size_t folds = 0;           // left at the end
};

// Local repair: the smoothing step on the vertices of invalid triangles grown by r rings
// (others fixed), in chunks of 50 iterations; r grows when a chunk did not lower the
// fold count. Stops at 0 folds, after max_iterations, or when should_stop() says so.
RepairStats local_repair(LaiChengSmoother& smoother, std::span<Vec3> q, size_t folds,
                         size_t max_iterations, const std::function<bool()>& should_stop);

// Fold-safe smoothing steps: the Lai-Cheng step for every vertex, then every vertex whose
// move invalidated a triangle that was valid backs off (half steps, up to 12, then stays),
// so a fold-free map stays fold-free while moving as far toward the smoothed map as it
// can. Returns the folds left (only those the map had before). Stops early when
// should_stop (may be empty) says so: each step is a pass over the whole level.
size_t fold_safe_steps(LaiChengSmoother& smoother, std::span<Vec3> q, size_t steps,
                       const std::function<bool()>& should_stop = {});

}  // namespace spheremap
