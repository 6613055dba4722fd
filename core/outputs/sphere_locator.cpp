#include "core/outputs/sphere_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/mesh/sphere_geometry.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {
namespace {

// Whether `p` may be in the spherical triangle (a, b, c) as far as the edge-plane tests
// (with locate's tolerances, up to 1e-9) cannot tell: for a clearly positive triangle
// they are exact (the cone of a, b and c), so nothing more is asked. A thin one (its
// corners nearly on one great circle, where the tests with a tolerance hold near the
// antipodes too) also needs p on its corners' side. Asking that of every triangle wrongly
// left out points of large, obtuse ones (an edge over 90 degrees: dot(a + b + c, p) < 0
// near the far corner), which certified maps of coarse parts have: samples went unlocated.
bool in_front(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  return triple_product(a, b, c) > 1e-6 || dot(a + b + c, p) > 0;
}

}  // namespace

SphereLocator::SphereLocator(std::span<const Vec3> sphere, std::span<const Triangle> triangles)
    : sphere_(sphere), triangles_(triangles) {
  // About two triangles per occupied cell: the sphere meets ~6 r^2 of the r^3 cells.
  resolution_ = std::clamp(static_cast<int>(std::sqrt(triangles.size() / 12.0)), 1, 256);
  const size_t cells = static_cast<size_t>(resolution_) * resolution_ * resolution_;
  auto cell_range = [&](const Triangle& t, std::array<int, 3>& lo, std::array<int, 3>& hi) {
    const Vec3 &a = sphere_[t[0]], &b = sphere_[t[1]], &c = sphere_[t[2]];
    // The patch is the chord triangle's central projection, each point p moved 1 - |p| out:
    // it lies within the corners' box widened by 1 - (the triangle's distance from the
    // origin). (The chord plane's distance, used before, is smaller: a small sliver's plane
    // can pass through the origin, and such a triangle was listed in every cell its box
    // widened by 1 meets: carbon-sphere.glb's map, 158K triangles, cost 447M cell visits
    // and 5.4 s to list.)
    const double nearest = norm(closest_on_triangle(Vec3{0, 0, 0}, a, b, c));
    const double bulge = 1 - std::min(nearest, 1.0) + 1e-9;
    for (int k = 0; k < 3; ++k) {
      const double mn = std::min({a[k], b[k], c[k]}) - bulge;
      const double mx = std::max({a[k], b[k], c[k]}) + bulge;
      lo[k] = std::clamp(static_cast<int>((mn + 1) * 0.5 * resolution_), 0, resolution_ - 1);
      hi[k] = std::clamp(static_cast<int>((mx + 1) * 0.5 * resolution_), 0, resolution_ - 1);
    }
  };
  // Queries are unit vectors, so only cells that meet the unit sphere are listed: a
  // triangle as large as a hemisphere (a doubled sheet's map has some along its seams)
  // has a box of all r^3 cells, of which ~6 r^2 meet the sphere (a scan's 40 parts:
  // 30 s and 600 MB of cell lists, where each cell's own list is all a query reads).
  // Per axis index: the least and largest squared coordinate over the cell's extent.
  std::vector<double> near2(static_cast<size_t>(resolution_)), far2(near2.size());
  for (int i = 0; i < resolution_; ++i) {
    const double lo = -1 + 2.0 * i / resolution_, hi = -1 + 2.0 * (i + 1) / resolution_;
    near2[static_cast<size_t>(i)] = lo <= 0 && hi >= 0 ? 0 : std::min(lo * lo, hi * hi);
    far2[static_cast<size_t>(i)] = std::max(lo * lo, hi * hi);
  }
  constexpr double kShell = 1e-6;  // rounding of a unit vector, with a wide margin
  auto meets_sphere = [&](int i, int j, int k) {
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j), c = static_cast<size_t>(k);
    return near2[a] + near2[b] + near2[c] <= (1 + kShell) * (1 + kShell) &&
           far2[a] + far2[b] + far2[c] >= (1 - kShell) * (1 - kShell);
  };
  std::vector<uint32_t> count(cells + 1, 0);
  // Along a column (i, j), the cells that meet the shell lie where B <= z^2 <= A (A, B from
  // the column's nearest and farthest x^2 + y^2): two runs of k, found from the roots with a
  // cell's margin and then tested as before, so a triangle as large as a hemisphere costs
  // r^2 cells, not r^3 (scorpion's map: 1.1 s of its remesh went to the r^3 scan).
  const auto index_of = [&](double v) {
    return static_cast<int>(std::floor((v + 1) * 0.5 * resolution_));
  };
  auto for_cells = [&](const Triangle& t, auto&& visit) {
    std::array<int, 3> lo, hi;
    cell_range(t, lo, hi);
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j) {
        const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j);
        const double most = (1 + kShell) * (1 + kShell) - near2[a] - near2[b];
        if (most < 0) continue;
        const double least = std::max(0.0, (1 - kShell) * (1 - kShell) - far2[a] - far2[b]);
        const double outer = std::sqrt(most), inner = std::sqrt(least);
        const int first_end = std::min(hi[2], index_of(-inner) + 1);
        for (int k = std::max(lo[2], index_of(-outer) - 1); k <= first_end; ++k)
          if (meets_sphere(i, j, k))
            visit((static_cast<size_t>(i) * resolution_ + j) * resolution_ + k);
        const int second_end = std::min(hi[2], index_of(outer) + 1);
        for (int k = std::max({lo[2], index_of(inner) - 1, first_end + 1}); k <= second_end; ++k)
          if (meets_sphere(i, j, k))
            visit((static_cast<size_t>(i) * resolution_ + j) * resolution_ + k);
      }
  };
  for (const Triangle& t : triangles_) for_cells(t, [&](size_t c) { ++count[c + 1]; });
  for (size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
  cell_start_ = count;
  cell_triangles_.resize(count[cells]);
  for (uint32_t t = 0; t < triangles_.size(); ++t)
    for_cells(triangles_[t], [&](size_t c) { cell_triangles_[count[c]++] = t; });
}

size_t SphereLocator::cell_of(const Vec3& p) const {
  auto index = [&](double v) {
    return static_cast<size_t>(
        std::clamp(static_cast<int>((v + 1) * 0.5 * resolution_), 0, resolution_ - 1));
  };
  return (index(p.x) * resolution_ + index(p.y)) * resolution_ + index(p.z);
}

bool SphereLocator::contains(uint32_t t, const Vec3& p, double tolerance) const {
  const Vec3 &a = sphere_[triangles_[t][0]], &b = sphere_[triangles_[t][1]],
             &c = sphere_[triangles_[t][2]];
  if (!in_front(a, b, c, p)) return false;
  return triple_product(a, b, p) >= -tolerance && triple_product(b, c, p) >= -tolerance &&
         triple_product(c, a, p) >= -tolerance;
}

SphereHit SphereLocator::hit(uint32_t t, const Vec3& p) const {
  const Vec3 &a = sphere_[triangles_[t][0]], &b = sphere_[triangles_[t][1]],
             &c = sphere_[triangles_[t][2]];
  std::array<double, 3> w = {std::max(0.0, triple_product(p, b, c)),
                             std::max(0.0, triple_product(a, p, c)),
                             std::max(0.0, triple_product(a, b, p))};
  const double sum = w[0] + w[1] + w[2];
  if (sum > 0)
    for (double& x : w) x /= sum;
  else
    w = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  return {t, w};
}

SphereHit SphereLocator::locate(const Vec3& p) const {
  const size_t cell = cell_of(p);
  // Exact first; then a tolerance for points on an edge that rounding puts just outside
  // both neighbours.
  for (double tolerance : {0.0, 1e-12, 1e-9})
    for (uint32_t i = cell_start_[cell]; i < cell_start_[cell + 1]; ++i)
      if (contains(cell_triangles_[i], p, tolerance)) return hit(cell_triangles_[i], p);
  return {};
}

SphereHit SphereLocator::nearest(const Vec3& p) const {
  auto outside = [&](uint32_t t) {  // the smallest edge-plane value: >= 0 inside
    const Vec3 &a = sphere_[triangles_[t][0]], &b = sphere_[triangles_[t][1]],
               &c = sphere_[triangles_[t][2]];
    if (!in_front(a, b, c, p)) return -std::numeric_limits<double>::infinity();
    return std::min({triple_product(a, b, p), triple_product(b, c, p), triple_product(c, a, p)});
  };
  uint32_t best = UINT32_MAX;
  double best_value = -std::numeric_limits<double>::infinity();
  auto consider = [&](uint32_t t) {
    const double value = outside(t);
    if (best == UINT32_MAX || value > best_value) best = t, best_value = value;
  };
  const size_t cell = cell_of(p);
  for (uint32_t i = cell_start_[cell]; i < cell_start_[cell + 1]; ++i) consider(cell_triangles_[i]);
  if (best == UINT32_MAX || best_value == -std::numeric_limits<double>::infinity())
    for (uint32_t t = 0; t < triangles_.size(); ++t) consider(t);
  return best == UINT32_MAX ? SphereHit{} : hit(best, p);
}

const SphereLocator& shared_or_own_locator(const SphereLocator* shared,
                                           std::optional<SphereLocator>& own,
                                           std::span<const Vec3> sphere,
                                           std::span<const Triangle> triangles) {
  if (shared) return *shared;
  return own.emplace(sphere, triangles);
}

}  // namespace spheremap
