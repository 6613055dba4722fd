#include "core/map/collapse_cost.h"

#include <algorithm>

namespace spheremap {

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

void CollapseCost::merge(uint32_t u, uint32_t v) {
  quadrics_[v] += quadrics_[u];
}

}  // namespace spheremap
