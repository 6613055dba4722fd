#include "core/map/float32_rescue.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "core/map/insertion.h"
#include "core/map/kernel_center.h"
#include "core/map/map_check.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// Whether the triangle fails as check_map counts it on the map rounded to float32.
// A valid triangle's area is 2 atan2(t, D) with D at most 4, so one whose triple product t
// exceeds 1e-12 is far above kDegenerateArea: the atan2 is left out for nearly all.
bool fails_in_float32(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 fa = rounded_to_float32(a), fb = rounded_to_float32(b), fc = rounded_to_float32(c);
  if (!is_valid_triangle(fa, fb, fc)) return true;
  return triple_product(fa, fb, fc) < 1e-12 && spherical_area(fa, fb, fc) < kDegenerateArea;
}

// The smallest float32 spherical area of v's star with v at p (invalid: -infinity).
double smallest_float32_area(std::span<const Vec3> sphere, const Vec3& p,
                             std::span<const uint32_t> ring) {
  const Vec3 fp = rounded_to_float32(p);
  double smallest = INFINITY;
  for (size_t k = 0; k < ring.size(); ++k) {
    const Vec3 fa = rounded_to_float32(sphere[ring[k]]);
    const Vec3 fb = rounded_to_float32(sphere[ring[(k + 1) % ring.size()]]);
    if (!is_valid_triangle(fp, fa, fb)) return -INFINITY;
    smallest = std::min(smallest, spherical_area(fp, fa, fb));
  }
  return smallest;
}

// v's ring in order (each star triangle (v, r_k, r_k+1) as oriented), or empty when its
// star is not one closed fan.
std::vector<uint32_t> ordered_ring(uint32_t v, std::span<const Triangle> triangles,
                                   std::span<const uint32_t> star) {
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // (r_k, r_k+1)
  for (const uint32_t t : star) {
    const Triangle& tri = triangles[t];
    const int at = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    edges.push_back({tri[(at + 1) % 3], tri[(at + 2) % 3]});
  }
  std::vector<uint32_t> ring{edges[0].first};
  uint32_t next = edges[0].second;
  while (next != ring[0] && ring.size() <= edges.size()) {
    ring.push_back(next);
    const auto e = std::find_if(edges.begin(), edges.end(),
                                [&](const auto& edge) { return edge.first == next; });
    if (e == edges.end()) return {};
    next = e->second;
  }
  if (next != ring[0] || ring.size() != edges.size()) return {};
  return ring;
}

}  // namespace

size_t rescue_float32(std::span<Vec3> sphere, std::span<const Triangle> triangles, int max_rounds) {
  // The stars, built only when something fails (the common case costs one scan).
  std::vector<uint32_t> offsets, stars;
  size_t moved = 0;
  for (int round = 0; round < max_rounds; ++round) {
    std::vector<uint32_t> corners;
    for (const Triangle& t : triangles)
      if (fails_in_float32(sphere[t[0]], sphere[t[1]], sphere[t[2]]))
        corners.insert(corners.end(), t.begin(), t.end());
    if (corners.empty()) break;
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    if (offsets.empty()) {
      offsets.assign(sphere.size() + 1, 0);
      for (const Triangle& t : triangles)
        for (const uint32_t v : t) ++offsets[v + 1];
      for (size_t v = 0; v < sphere.size(); ++v) offsets[v + 1] += offsets[v];
      stars.resize(offsets.back());
      std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
      for (uint32_t t = 0; t < triangles.size(); ++t)
        for (const uint32_t v : triangles[t]) stars[fill[v]++] = t;
    }
    size_t moved_now = 0;
    for (const uint32_t v : corners) {
      const std::span<const uint32_t> star(stars.data() + offsets[v], offsets[v + 1] - offsets[v]);
      // A closed fan has as many ring corners as triangles: a star kernel_center refuses
      // is skipped before its ring is ordered (O(star^2)).
      if (star.size() < 3 || star.size() > kKernelCenterMaxCorners) continue;
      const std::vector<uint32_t> ring = ordered_ring(v, triangles, star);
      if (ring.empty()) continue;
      std::vector<Vec3> ring_points(ring.size());
      for (size_t k = 0; k < ring.size(); ++k) ring_points[k] = sphere[ring[k]];
      const std::optional<Vec3> center = kernel_center(ring_points, sphere[v]);
      if (!center || !star_valid(sphere, *center, ring)) continue;
      if (smallest_float32_area(sphere, *center, ring) <=
          smallest_float32_area(sphere, sphere[v], ring))
        continue;
      sphere[v] = *center;
      ++moved_now;
    }
    moved += moved_now;
    if (moved_now == 0) break;
  }
  return moved;
}

}  // namespace spheremap
