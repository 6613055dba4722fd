#include "core/map/insertion.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/map/kernel_center.h"

#include "core/mesh/sphere_geometry.h"

namespace spheremap {

bool star_valid(std::span<const Vec3> q, const Vec3& p, std::span<const uint32_t> ring) {
  for (size_t k = 0; k < ring.size(); ++k)
    if (!is_valid_triangle(p, q[ring[k]], q[ring[(k + 1) % ring.size()]])) return false;
  return true;
}

namespace {

// Moves a valid placement toward the ring average while it stays valid (t = 1/2 .. 1/64):
// better-shaped triangles for the smoothing that follows.
Vec3 blend_toward(std::span<const Vec3> q, const Vec3& p, const Vec3& average,
                  std::span<const uint32_t> ring) {
  for (double t = 0.5; t >= 1.0 / 64; t *= 0.5) {
    const Vec3 blended = normalized_or((1 - t) * p + t * average, p);
    if (star_valid(q, blended, ring)) return blended;
  }
  return p;
}

}  // namespace

InsertionOutcome insert_vertex(std::span<Vec3> q, uint32_t u, uint32_t v,
                               std::span<const uint32_t> ring) {
  Vec3 sum;
  for (uint32_t w : ring) sum += q[w];
  const Vec3& qv = q[v];
  const Vec3 average = normalized_or(sum, qv);
  if (star_valid(q, average, ring)) {
    q[u] = average;
    return InsertionOutcome::kRingAverage;
  }

  // The kernel's Chebyshev centre: the placement farthest from every ring edge.
  std::vector<Vec3> corners(ring.size());
  for (size_t k = 0; k < ring.size(); ++k) corners[k] = q[ring[k]];
  if (auto center = kernel_center(corners, average); center && star_valid(q, *center, ring)) {
    q[u] = blend_toward(q, *center, average, ring);
    return InsertionOutcome::kKernelSearch;
  }

  // Star triangles at v: (u, v, wa) and (u, wb, v), so around v (counter-clockwise
  // about the outward normal) come wa, then u, then wb.
  const size_t k = static_cast<size_t>(std::find(ring.begin(), ring.end(), v) - ring.begin());
  const size_t m = ring.size();
  const Vec3 &wa = q[ring[(k + 1) % m]], &wb = q[ring[(k + m - 1) % m]];
  auto tangent = [&](const Vec3& w) { return normalized_or(w - dot(w, qv) * qv, Vec3{}); };
  const Vec3 ea = tangent(wa), eb = tangent(wb);
  double theta = std::atan2(dot(qv, cross(ea, eb)), dot(ea, eb));
  if (theta <= 0) theta += 2 * M_PI;
  const Vec3 direction = std::cos(theta / 2) * ea + std::sin(theta / 2) * cross(qv, ea);

  double step = INFINITY;
  for (uint32_t w : ring)
    if (w != v) step = std::min(step, norm(q[w] - qv));
  step *= 0.5;
  for (int halving = 0; halving < 60; ++halving, step *= 0.5) {
    const Vec3 p = normalized_or(qv + step * direction, qv);
    if (!star_valid(q, p, ring)) continue;
    q[u] = blend_toward(q, p, average, ring);
    return InsertionOutcome::kKernelSearch;
  }
  q[u] = normalized_or(qv + 1e-9 * direction, qv);
  return InsertionOutcome::kFailed;
}

}  // namespace spheremap
