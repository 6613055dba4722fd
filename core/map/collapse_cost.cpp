#include "core/map/collapse_cost.h"

#include <algorithm>

namespace spheremap {

// The squared edge length's weight next to the mean squared plane distance: the plane
// term decides wherever a collapse moves the surface by more than a hundredth of the edge.
// Chosen on the stress set and random limbed shapes (not the corpus): 1e-3 and 1e-5 gave
// the same or worse stretch there (BENCHMARKS.md, "What we measured on the way").
constexpr double kEdgeLengthWeight = 1e-4;

CollapseCost::CollapseCost(std::span<const Vec3> positions, std::span<const Triangle> triangles)
    : x_(positions), quadrics_(positions.size()) {
  for (const Triangle& t : triangles) {
    const Vec3 normal = cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    const double twice_area = norm(normal);
    if (!(twice_area > 0)) continue;  // a degenerate triangle has no plane
    const Vec3 n = (1 / twice_area) * normal;
    const double d = -dot(n, positions[t[0]]);
    for (uint32_t v : t) {
      Quadric& q = quadrics_[v];
      const double w = twice_area;
      q.a00 += w * n.x * n.x, q.a01 += w * n.x * n.y, q.a02 += w * n.x * n.z;
      q.a11 += w * n.y * n.y, q.a12 += w * n.y * n.z, q.a22 += w * n.z * n.z;
      q.b0 += w * d * n.x, q.b1 += w * d * n.y, q.b2 += w * d * n.z;
      q.c += w * d * d, q.weight += w;
    }
  }
}

double CollapseCost::operator()(uint32_t u, uint32_t v) const {
  Quadric q = quadrics_[u];
  q += quadrics_[v];
  const Vec3& p = x_[v];
  // The constant terms are added last, one at a time, as the hierarchy always summed
  // them: another rounding reorders ties (measured: a different stress-fingers hierarchy).
  const double error = p.x * (q.a00 * p.x + 2 * q.a01 * p.y + 2 * q.a02 * p.z) +
                       p.y * (q.a11 * p.y + 2 * q.a12 * p.z) + q.a22 * p.z * p.z +
                       2 * (q.b0 * p.x + q.b1 * p.y + q.b2 * p.z) + quadrics_[u].c + quadrics_[v].c;
  // Rounding can take an error of 0 slightly below it.
  const double mean = q.weight > 0 ? std::max(0.0, error) / q.weight : 0.0;
  return mean + kEdgeLengthWeight * squared_norm(x_[u] - p);
}

void CollapseCost::merge(uint32_t u, uint32_t v) {
  quadrics_[v] += quadrics_[u];
}

}  // namespace spheremap
