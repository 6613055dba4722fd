// The order of the collapse hierarchy (hierarchy.h): what removing u onto v costs.
//
// The quadric error of Garland & Heckbert: every input triangle gives its corners the
// squared distance to its plane, weighted by its area; a vertex's quadric sums those of
// the triangles it stands for, and a collapse u -> v costs the mean squared distance of
// v's position from the planes of u and v together. A small multiple of the squared edge
// length breaks the ties on flat parts (where every quadric error is 0) in favour of short
// edges, as the plain shortest-edge order did.
//
// Why not the shortest edge alone: on a long thin part the shortest edges are those
// around it, so a shortest-edge hierarchy collapses the part to a needle first, and the
// coarse levels, optimized to convergence, lay out a shape that is not there. Measured
// (standard, stretch L2): very long tube 10.6 -> 5.7 (SphereParam default 6.4), beast
// 2.02 -> 1.90, scorpion 2.54 -> 2.40, horse 1.64 -> 1.60; BENCHMARKS.md has the rest.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

class CollapseCost {
 public:
  // Precondition: every index of `triangles` is below positions.size().
  CollapseCost(std::span<const Vec3> positions, std::span<const Triangle> triangles);

  // The cost of moving u onto v (both alive). Inline (below): the hierarchy asks it about
  // 17 times per vertex; inlined, horse's hierarchy_bench run takes 885M -> 844M instructions.
  double operator()(uint32_t u, uint32_t v) const;

  // After the collapse u -> v: v stands for u's planes too.
  void merge(uint32_t u, uint32_t v);

 private:
  // Sum of w (n.p + d)^2 over planes (n, d): p^T A p + 2 b.p + c, and the sum of w.
  struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
    double b0 = 0, b1 = 0, b2 = 0, c = 0, weight = 0;

    Quadric& operator+=(const Quadric& o) {
      a00 += o.a00, a01 += o.a01, a02 += o.a02, a11 += o.a11, a12 += o.a12, a22 += o.a22;
      b0 += o.b0, b1 += o.b1, b2 += o.b2, c += o.c, weight += o.weight;
      return *this;
    }
  };

  std::span<const Vec3> x_;
  std::vector<Quadric> quadrics_;
};

// The squared edge length's weight next to the mean squared plane distance: the plane
// term decides wherever a collapse moves the surface by more than a hundredth of the edge.
// Chosen on the stress set and random limbed shapes (not the corpus): 1e-3 and 1e-5 gave
// the same or worse stretch there (BENCHMARKS.md, "What we measured on the way").
inline constexpr double kEdgeLengthWeight = 1e-4;

inline double CollapseCost::operator()(uint32_t u, uint32_t v) const {
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

}  // namespace spheremap
