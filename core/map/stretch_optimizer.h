// Stretch optimization of a fold-free spherical map (ALGORITHM §F, after Praun & Hoppe).
//
// Energy, per triangle T weighted by its surface area A_T:
//   E_T = A_T [ 1/2 (g1^2 + g2^2) + lambda 1/2 (g1^-2 + g2^-2) ]
// with g1 >= g2 the singular values of the affine map from the chord triangle on the
// sphere (the sphere scaled to the surface's total area) to the surface triangle. The
// first term is Sander's L2 stretch; it grows like 1 / (chord area)^2, so it is itself a
// barrier against squeezed triangles, which is what keeps float32 output fold-free.
// Both terms reduce to one quadratic form in the chord corners with constant weights
// c_i = (x_j - x_i) . (x_k - x_i) of the surface triangle:
//   N_T = sum_i c_i |q_j - q_k|^2,  E_T = A_T N_T s^2 / 8 (1 / A_P^2 + lambda / A_T^2)
// where A_P = s^2 det[q_0, q_1, q_2] / 2 and s^2 = surface area / sum of those. For small
// triangles det / 2 is the chord triangle's area (its plane is ~1 from the centre); unlike
// the chord area it also vanishes when a large triangle's corners approach a great
// circle, so the barrier guards the orientation test itself (coarse levels have such
// triangles: measured, a 5-vertex level with chord areas ~1 and det 5e-5).
//
// Each sweep moves every active vertex by one Newton step in its tangent plane (2x2
// Hessian from differences of the analytic gradient, eigenvalues clamped positive),
// limited to 0.8 of the exact largest flip-free step (each star determinant is linear in
// the step), then Armijo backtracking, then renormalized. Vertices move one colour class
// at a time (no two adjacent), so the result is bit-identical for any thread count, and
// every triangle stays valid (§B1) after every move: a fold-free map stays fold-free.
// After the sweeps of a whole-mesh call on a small mesh, Newton steps move all vertices at
// once (stretch_newton.h). Before the sweeps of a whole-mesh call, the vertices of triangles whose
// energy density is far above the median (what an insertion squeezed) are moved alone until they
// are relieved, so the sweeps start from a map without such spikes.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

struct StretchOptions {
  double lambda = 0.1;              // weight of the inverse-stretch (symmetric Dirichlet) term
  size_t max_sweeps = 60;           // per call
  double relative_decrease = 1e-3;  // stop when a sweep lowers the energy by less than this
  double active_tolerance = 1e-3;   // a vertex stays active while it moves > this x its edges
  int threads = 0;                  // 0 = all cores
  // A vertex first tries this multiple of its Newton step (when its triangles allow it and
  // the energy drops enough), then the Newton step: nonlinear successive over-relaxation.
  // Gauss-Seidel sweeps shrink smooth errors slowly (each vertex moves against a ring that
  // has not moved yet); overshooting each step carries a change further per sweep.
  // Measured at 1.5 against 1 (BENCHMARKS.md, session 52; 55 meshes: corpus, stress,
  // random shapes): 16% fewer vertex updates at standard, 19% at fast, stretch and area
  // distortion lower on average.
  double over_relaxation = 1.5;
  // Before the sweeps, move only the vertices of triangles far above the median energy
  // until none is left (a whole-mesh optimization only, `start` empty).
  bool relieve_hot_spots = true;
  // After the sweeps of a whole-mesh call on at most this many vertices, Newton steps of
  // all vertices at once (stretch_newton.h) while each lowers the energy by over 10x
  // relative_decrease, at most max_newton_steps: they converge where the sweeps crawl.
  size_t newton_max_vertices = 0;
  size_t max_newton_steps = 8;
};

struct StretchStats {
  size_t sweeps = 0;
  double vertex_updates = 0;                    // Newton steps taken, all sweeps
  size_t newton_steps = 0;                      // whole-map Newton steps after the sweeps
  double initial_energy = 0, final_energy = 0;  // per unit surface area (1 + lambda: isometry)
};

// Lowers the energy of the fold-free map q of `triangles` (surface positions x, both per
// vertex; triangles oriented so a valid map has positive determinants). Keeps q
// fold-free and on the unit sphere. should_stop() is polled between colour classes.
// `start`: the vertices active in the first sweep (empty: all); the active set then
// grows to the neighbours of whatever moves. `area_scale`: per triangle, a factor on its
// surface area (its shape kept; empty: 1), so a coarse level can weigh each triangle by
// the fine surface it stands for.
// Precondition: every triangle valid in q (is_valid_triangle).
StretchStats optimize_stretch(std::span<const Vec3> x, std::span<const Triangle> triangles,
                              std::span<Vec3> q, const StretchOptions& options,
                              const std::function<bool()>& should_stop,
                              std::span<const uint32_t> start = {},
                              std::span<const double> area_scale = {});

// The safety net before certification: vertices of the triangles a reader could not
// tell from a fold, that is spherical area below 100 x kDegenerateArea in double, or not
// valid once the positions are rounded to float32 (what a GLB stores).
std::vector<uint32_t> uncertain_vertices(std::span<const Vec3> q,
                                         std::span<const Triangle> triangles);

}  // namespace spheremap
