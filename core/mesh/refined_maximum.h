// The largest distance to a surface over every point of some triangles, not only at their
// corners and centroids.
//
// A distance to a surface is 1-Lipschitz: within r of a point measured at d it is at most
// d + r. So a triangle measured at its corners and centroid is bounded by the smallest of
// those distances plus how far the triangle reaches from that point. Branch and bound: the
// piece whose bound is farthest above the largest distance found so far (plus a tolerance)
// is cut into four at its edge midpoints and the pieces measured, until no bound is above
// it, within a budget of queries. A long triangle over a gap of the other surface (a remesh
// across a hole's opening) has its corners on that surface and its middle far from it:
// measured at corners and centroid alone, one such remesh read 3.1% from its original where
// an edge midpoint is 4.4% away.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

// Two figures measured at once (e.g. to all of a surface and to part of it); a caller with
// one measures it twice in the same entry.
using DistancePair = std::array<double, 2>;

// What one point measured: its distance per figure and, per figure, the triangle of the
// other surface nearest to it (kNoNearest when not known).
inline constexpr uint32_t kNoNearest = UINT32_MAX;
struct PointMeasure {
  DistancePair distance{0, 0};
  std::array<uint32_t, 2> nearest{kNoNearest, kNoNearest};
};

constexpr int kMaxRefinementDepth = 8;  // a piece's edges down to 1/256 of its triangle's
// The budget: this many queries per triangle given, or of the other surface when it has
// more (a box's 12 triangles against a remesh of 32,768 need about as many queries as the
// remesh has triangles: with 12 per box triangle its maximum was left open, said to be at
// most 5.4% where it is 0.92%), at most kMaxRefinementQueries, plus 4,096, and at most
// kMaxWaitingPieces cut pieces waiting (208 bytes each). Two surfaces
// that nearly coincide have every bound above a maximum near 0 and would be cut to the
// depth limit. Measured on remeshes at N = 128 (32,768 triangles) against their originals:
// horse needed 6.9 queries per remesh triangle to settle (its maximum 4% above what 2 per
// triangle found), spot 6.2 (12% above).
constexpr size_t kRefinementQueriesPerTriangle = 12;
constexpr size_t kMaxRefinementQueries = size_t{1} << 22;
constexpr size_t kMaxWaitingPieces = size_t{1} << 18;
constexpr size_t kRefinementBatch = 256;  // pieces cut in parallel between updates

// The largest distance over the points of `triangles` (each figure over the triangles that
// count for it, counts(t, figure)), at least `reached`, to within `tolerance` (per figure)
// of the true maximum where the depth and the budget allow. vertex_measure (per position)
// and centroid_measure (per triangle) are what was already measured there; measure(p)
// measures one more point, safe to call from several threads; `other_triangles`: how many
// the surface it measures to has (for the budget). The result does not depend on `threads`.
// `should_stop` (may be null) is asked before each batch; true throws InputError("stopped").
//
// `give_up`: once a figure's largest distance found reaches its entry, the search stops
// there, unsettled (a caller that keeps only a maximum under some other needs no more).
//
// `to_triangle` (may be null): the distance from a point to one triangle of the other
// surface. With it a piece is bounded more tightly too: the distance to one triangle T is
// convex (T is), so over a piece it is largest at a corner, and the distance to the surface
// is at most that to T: the piece's figure is at most the largest of its corners' distances
// to T, for T the triangle nearest any of its measured points. Where the two surfaces lie
// close (a remesh on its original), a piece over one triangle of the other settles at once,
// where the Lipschitz bound alone (a measured distance plus the piece's reach) cuts it
// until the pieces are about the tolerance across.
struct RefinedMaximum {
  DistancePair reached{0, 0};  // the largest distance measured at a point
  // What the true maximum is at most: reached + tolerance where every piece settled, else
  // the largest bound left open when the depth or the budget ran out (`settled` false).
  DistancePair at_most{0, 0};
  std::array<bool, 2> settled{true, true};
};
RefinedMaximum refined_maximum(
    std::span<const Vec3> positions, std::span<const Triangle> triangles,
    std::span<const PointMeasure> vertex_measure, std::span<const PointMeasure> centroid_measure,
    DistancePair reached, DistancePair tolerance, const std::function<bool(size_t, int)>& counts,
    const std::function<PointMeasure(const Vec3&)>& measure, size_t other_triangles, int threads,
    const std::function<bool()>* should_stop,
    const std::function<double(const Vec3&, uint32_t)>* to_triangle = nullptr,
    DistancePair give_up = {INFINITY, INFINITY});

}  // namespace spheremap
