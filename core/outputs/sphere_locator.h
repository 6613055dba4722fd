// Point location in a spherical triangulation (a bijective map): which triangle holds a
// point of the sphere, and its barycentric coordinates there. A uniform grid over the
// cube [-1,1]^3 lists every triangle in the cells its spherical patch may touch (its
// corners' box widened by the patch's bulge), so a query tests a handful of triangles.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

struct SphereHit {
  uint32_t triangle = UINT32_MAX;  // UINT32_MAX: not found (the map is not bijective)
  // Of the point's central projection onto the chord triangle: the same point of the
  // spherical triangle, and what interpolates attributes of the original surface.
  std::array<double, 3> barycentric{};
};

class SphereLocator {
 public:
  // Preconditions: sphere points of unit length; triangles positively oriented (a bijective
  // map's oriented triangles). Both must outlive the locator.
  SphereLocator(std::span<const Vec3> sphere, std::span<const Triangle> triangles);

  SphereHit locate(const Vec3& point) const;
  // When locate finds nothing (a gap between triangles): the triangle the point is least
  // outside of (the largest of its three edge-plane distances' smallest), over the point's
  // cell, else over all triangles; its barycentric coordinates clamped to it. UINT32_MAX
  // only without triangles. So a sample in a gap lands on the surface next to it, not at
  // the model's origin.
  SphereHit nearest(const Vec3& point) const;
  // How many (cell, triangle) entries the grid holds: its memory, and its build's work.
  size_t listed() const { return cell_triangles_.size(); }

 private:
  size_t cell_of(const Vec3& p) const;
  bool contains(uint32_t t, const Vec3& p, double tolerance) const;
  SphereHit hit(uint32_t t, const Vec3& p) const;

  std::span<const Vec3> sphere_;
  std::span<const Triangle> triangles_;
  int resolution_ = 1;
  std::vector<uint32_t> cell_start_;  // CSR: triangles of cell c are [start[c], start[c+1])
  std::vector<uint32_t> cell_triangles_;
};

// `shared` when given, else a locator of `sphere` and `triangles` built into `own`: for
// functions that take a caller's locator (sampled once for several outputs) or build one.
const SphereLocator& shared_or_own_locator(const SphereLocator* shared,
                                           std::optional<SphereLocator>& own,
                                           std::span<const Vec3> sphere,
                                           std::span<const Triangle> triangles);

}  // namespace spheremap
