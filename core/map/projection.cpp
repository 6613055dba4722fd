#include "core/map/projection.h"

#include <algorithm>

#include "core/mesh/parallel.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {

std::vector<Vec3> project_to_sphere(std::span<const Vec3> positions, const SparseMatrix& A,
                                    int presmooth_steps, int threads) {
  const size_t n = positions.size();
  threads = resolve_threads(threads);
  std::vector<Vec3> m(positions.begin(), positions.end()), next(n);
  for (int k = 0; k < presmooth_steps; ++k) {
    parallel_for(n, threads, [&](size_t i) { next[i] = A.row_times(i, m); });
    m.swap(next);
    // Many steps shrink the shape toward its centroid; re-centre and rescale (directions
    // from C do not change) so long pre-smoothing stays well inside double precision.
    Vec3 mean;
    for (const Vec3& v : m) mean += v;
    mean *= 1.0 / static_cast<double>(n);
    double spread = 0;
    for (const Vec3& v : m) spread = std::max(spread, norm(v - mean));
    if (spread > 0)
      for (Vec3& v : m) v = (v - mean) * (1.0 / spread);
  }
  Vec3 mean;
  for (const Vec3& v : m) mean += v;
  mean *= 1.0 / static_cast<double>(n);
  Vec3 weighted;
  double total = 0;
  for (const Vec3& v : m) {
    const double w = norm(v - mean);
    weighted += w * v;
    total += w;
  }
  const Vec3 center = total > 0 ? weighted * (1.0 / total) : mean;

  std::vector<Vec3> q(n);
  for (size_t i = 0; i < n; ++i) q[i] = normalized_or(m[i] - center, Vec3{});
  for (size_t i = 0; i < n; ++i) {
    if (squared_norm(q[i]) > 0) continue;
    Vec3 sum;
    for (uint32_t k = A.offsets[i]; k < A.offsets[i + 1]; ++k) sum += q[A.columns[k]];
    q[i] = normalized_or(sum, Vec3{0, 0, 1});
  }
  return q;
}

}  // namespace spheremap
