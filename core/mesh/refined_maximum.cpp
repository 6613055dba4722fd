#include "core/mesh/refined_maximum.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/stop_check.h"

namespace spheremap {
namespace {

using ToTriangle = std::function<double(const Vec3&, uint32_t)>;

// A triangle or one of its pieces, with what was measured at its corners and centroid, and
// the largest each figure can take on it (bounded()).
struct Piece {
  std::array<Vec3, 3> corner;
  std::array<PointMeasure, 3> at;
  PointMeasure centre;
  int depth = 0;
  DistancePair cap{0, 0};
};

Vec3 centroid(const std::array<Vec3, 3>& c) {
  return (c[0] + c[1] + c[2]) * (1.0 / 3);
}

// A bound of the largest distance figure k can take on the piece, tightened only as far
// as `settles` (a bound at or under it settles the piece: what is tighter changes nothing
// but the order pieces are cut in). From each measured point: its distance plus how far
// the piece reaches from it (the distance is 1-Lipschitz). Then, with `to_triangle`, for
// each other triangle nearest a measured point: the largest distance of a corner to it
// (convex over the piece; the surface is at least as near).
double bound(const Piece& piece, int k, const ToTriangle* to_triangle, double settles) {
  const std::array<Vec3, 3>& c = piece.corner;
  const Vec3 middle = centroid(c);
  double reach = 0;
  for (const Vec3& p : c) reach = std::max(reach, norm(p - middle));
  double out = piece.centre.distance[k] + reach;
  for (int i = 0; i < 3; ++i) {
    const double from_corner = std::max(norm(c[(i + 1) % 3] - c[i]), norm(c[(i + 2) % 3] - c[i]));
    out = std::min(out, piece.at[i].distance[k] + from_corner);
  }
  if (!to_triangle) return out;
  const std::array<uint32_t, 4> nearest = {piece.centre.nearest[k], piece.at[0].nearest[k],
                                           piece.at[1].nearest[k], piece.at[2].nearest[k]};
  for (size_t j = 0; j < nearest.size() && out > settles; ++j) {
    const uint32_t t = nearest[j];
    if (t == kNoNearest ||
        std::find(nearest.begin(), nearest.begin() + j, t) != nearest.begin() + j)
      continue;
    double largest = 0;
    for (int i = 0; i < 3 && largest < out; ++i)
      largest = std::max(largest, (*to_triangle)(c[i], t));
    out = std::min(out, largest);
  }
  return out;
}

// The piece with its bounds; `settles`: per figure, the best distance so far plus the
// tolerance (it only grows, so a bound under it stays under).
Piece bounded(Piece piece, const ToTriangle* to_triangle, const DistancePair& settles) {
  for (int k = 0; k < 2; ++k) piece.cap[k] = bound(piece, k, to_triangle, settles[k]);
  return piece;
}

// How far the piece's bound is above what would settle it, over the figures it counts for
// (positive: worth cutting).
double excess(const Piece& piece, const DistancePair& best, const DistancePair& tolerance,
              const std::array<bool, 2>& counted) {
  double out = -INFINITY;
  for (int k = 0; k < 2; ++k)
    if (counted[k]) out = std::max(out, piece.cap[k] - (best[k] + tolerance[k]));
  return out;
}

// A triangle waiting to be cut (its piece is made again when taken).
struct QueuedTriangle {
  double over;  // excess() when queued: an upper bound of it later (best only grows)
  uint32_t triangle;
  bool operator<(const QueuedTriangle& other) const { return over < other.over; }
};

// A piece cut from a triangle, waiting to be cut in turn.
struct QueuedPiece {
  double over;
  uint32_t triangle;
  Piece piece;
  bool operator<(const QueuedPiece& other) const { return over < other.over; }
};

// The four pieces of a piece cut at its edge midpoints, each with its measures and bounds.
struct Cut {
  std::array<Piece, 4> children;
  std::array<DistancePair, 7> measured;  // the 3 midpoints, then the 4 centroids
};

Cut cut(const Piece& piece, const std::function<PointMeasure(const Vec3&)>& measure,
        const ToTriangle* to_triangle, const DistancePair& settles) {
  const std::array<Vec3, 3>& c = piece.corner;
  const std::array<PointMeasure, 3>& a = piece.at;
  const std::array<Vec3, 3> middle = {0.5 * (c[0] + c[1]), 0.5 * (c[1] + c[2]),
                                      0.5 * (c[2] + c[0])};
  const std::array<PointMeasure, 3> m = {measure(middle[0]), measure(middle[1]),
                                         measure(middle[2])};
  Cut out;
  for (int i = 0; i < 3; ++i) out.measured[i] = m[i].distance;
  out.children = {Piece{{c[0], middle[0], middle[2]}, {a[0], m[0], m[2]}, {}, piece.depth + 1},
                  Piece{{middle[0], c[1], middle[1]}, {m[0], a[1], m[1]}, {}, piece.depth + 1},
                  Piece{{middle[2], middle[1], c[2]}, {m[2], m[1], a[2]}, {}, piece.depth + 1},
                  Piece{middle, m, {}, piece.depth + 1}};
  for (int i = 0; i < 4; ++i) {
    out.children[i].centre = measure(centroid(out.children[i].corner));
    out.measured[3 + i] = out.children[i].centre.distance;
    out.children[i] = bounded(out.children[i], to_triangle, settles);
  }
  return out;
}

}  // namespace

RefinedMaximum refined_maximum(
    std::span<const Vec3> positions, std::span<const Triangle> triangles,
    std::span<const PointMeasure> vertex_measure, std::span<const PointMeasure> centroid_measure,
    DistancePair reached, DistancePair tolerance, const std::function<bool(size_t, int)>& counts,
    const std::function<PointMeasure(const Vec3&)>& measure, size_t other_triangles, int threads,
    const std::function<bool()>* should_stop, const ToTriangle* to_triangle, DistancePair give_up) {
  DistancePair best = reached;
  // The largest bound of a piece left unsettled (at the depth limit, or open at the end).
  DistancePair unsettled{-INFINITY, -INFINITY};
  const auto leave = [&](const Piece& piece, const std::array<bool, 2>& counted_for) {
    for (int k = 0; k < 2; ++k)
      if (counted_for[k]) unsettled[k] = std::max(unsettled[k], piece.cap[k]);
  };
  const size_t n = triangles.size();
  std::vector<std::array<bool, 2>> counted(n);
  auto root = [&](size_t t) {
    const Triangle& tri = triangles[t];
    return bounded(Piece{{positions[tri[0]], positions[tri[1]], positions[tri[2]]},
                         {vertex_measure[tri[0]], vertex_measure[tri[1]], vertex_measure[tri[2]]},
                         centroid_measure[t],
                         0},
                   to_triangle, {best[0] + tolerance[0], best[1] + tolerance[1]});
  };
  // Two heaps, the most promising first: whole triangles (16 bytes each, however many are
  // open) and the pieces cut from them (bounded by kMaxWaitingPieces).
  std::vector<QueuedTriangle> triangles_open;
  std::vector<QueuedPiece> pieces_open;
  for (size_t t = 0; t < n; ++t) {
    counted[t] = {counts(t, 0), counts(t, 1)};
    const double over = excess(root(t), best, tolerance, counted[t]);
    if (over > 0) triangles_open.push_back({over, static_cast<uint32_t>(t)});
  }
  std::make_heap(triangles_open.begin(), triangles_open.end());
  const size_t budget = std::min(kRefinementQueriesPerTriangle * std::max(n, other_triangles),
                                 kMaxRefinementQueries) +
                        4096;
  size_t queries = 0;
  const StopCheck stop(should_stop);
  std::vector<Piece> batch;
  std::vector<uint32_t> batch_triangle;
  std::vector<Cut> cuts;
  const auto given_up = [&] { return best[0] >= give_up[0] || best[1] >= give_up[1]; };
  while ((!triangles_open.empty() || !pieces_open.empty()) && queries < budget &&
         pieces_open.size() + 4 * kRefinementBatch <= kMaxWaitingPieces && !given_up()) {
    stop.check();
    // The most promising pieces still open, cut in parallel; the best figures and the heaps
    // are then updated in the batch's order (the same for any thread count).
    batch.clear(), batch_triangle.clear();
    while (batch.size() < kRefinementBatch && (!triangles_open.empty() || !pieces_open.empty())) {
      const bool whole =
          pieces_open.empty() ||
          (!triangles_open.empty() && pieces_open.front().over < triangles_open.front().over);
      Piece piece;
      uint32_t triangle;
      if (whole) {
        std::pop_heap(triangles_open.begin(), triangles_open.end());
        triangle = triangles_open.back().triangle;
        piece = root(triangle);
        triangles_open.pop_back();
      } else {
        std::pop_heap(pieces_open.begin(), pieces_open.end());
        triangle = pieces_open.back().triangle;
        piece = pieces_open.back().piece;
        pieces_open.pop_back();
      }
      if (!(excess(piece, best, tolerance, counted[triangle]) > 0)) continue;
      if (piece.depth < kMaxRefinementDepth)
        batch.push_back(piece), batch_triangle.push_back(triangle);
      else
        leave(piece, counted[triangle]);
    }
    cuts.resize(batch.size());
    const DistancePair settles = {best[0] + tolerance[0], best[1] + tolerance[1]};
    parallel_for(batch.size(), resolve_threads(threads),
                 [&](size_t i) { cuts[i] = cut(batch[i], measure, to_triangle, settles); });
    queries += 7 * batch.size();
    for (size_t i = 0; i < batch.size(); ++i) {
      const std::array<bool, 2>& c = counted[batch_triangle[i]];
      for (const DistancePair& d : cuts[i].measured)
        for (int k = 0; k < 2; ++k)
          if (c[k]) best[k] = std::max(best[k], d[k]);
    }
    for (size_t i = 0; i < batch.size(); ++i) {
      const uint32_t triangle = batch_triangle[i];
      for (const Piece& child : cuts[i].children) {
        const double over = excess(child, best, tolerance, counted[triangle]);
        if (!(over > 0)) continue;
        pieces_open.push_back({over, triangle, child});
        std::push_heap(pieces_open.begin(), pieces_open.end());
      }
    }
  }
  if (given_up()) {  // what is open was not searched: nothing is said of it
    RefinedMaximum out;
    out.reached = best;
    out.at_most = {INFINITY, INFINITY};
    out.settled = {false, false};
    return out;
  }
  // What the budget left open (a bound only grows less as best grows: taken again here).
  for (const QueuedTriangle& open : triangles_open)
    leave(root(open.triangle), counted[open.triangle]);
  for (const QueuedPiece& open : pieces_open) leave(open.piece, counted[open.triangle]);
  RefinedMaximum out;
  out.reached = best;
  for (int k = 0; k < 2; ++k) {
    out.at_most[k] = best[k] + tolerance[k];
    if (unsettled[k] > out.at_most[k]) out.at_most[k] = unsettled[k], out.settled[k] = false;
  }
  return out;
}

}  // namespace spheremap
