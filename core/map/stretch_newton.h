// One projected-Newton step of a stretch energy over the whole map (ALGORITHM §F).
//
// The per-vertex sweeps of optimize_stretch are nonlinear Gauss-Seidel: each vertex moves
// against its ring held still. Where the optimum asks many vertices to move together
// against stiff triangles (a cylinder's rim sliding toward a pole between fan caps and
// long side slivers) they converge like a diffusion over the whole chain: measured on a
// 256-segment CAD cylinder, 60 sweeps left the energy at 3.33 where 780 reach 1.93.
// A Newton step sees the coupling: every triangle's Hessian (tangent coordinates, made
// positive semi-definite), summed and solved by sparse LDLT, moves all vertices at once.
// It costs a factorization, so the caller keeps it to small levels.
#pragma once

#include <span>

#include "core/mesh/mesh.h"

namespace spheremap {

// Triangle (q_0, q_1, q_2) of the map, with A = det[q_0, q_1, q_2] / 2 and
// N = sum_i c[i] |q_j - q_k|^2 over the edges (j, k) opposite each corner i:
//   E = stretch N / (s^2 A^2) + inverse s^2 N
// where s^2 = surface area / sum of all A scales the sphere to the surface's area (the
// energy does not change when the map is scaled).
struct TriangleEnergy {
  double c[3];
  double stretch, inverse;
};

// Moves every vertex of the fold-free map q (unit vectors) by one Newton step in its
// tangent plane (s^2 held at its value in q), limited to 0.8 of the largest step that
// keeps every triangle valid along the way (each determinant is a cubic in the step),
// then Armijo backtracking on the total energy (s^2 of each candidate), each candidate
// checked by the robust orientation test. Keeps q fold-free and on the unit sphere.
// Returns the relative decrease of the total energy (0 when no step was taken).
// Precondition: every triangle valid in q (is_valid_triangle).
double newton_step(std::span<const Triangle> triangles, std::span<const TriangleEnergy> energy,
                   double surface_area, std::span<Vec3> q, int threads);

// The first t in (0, limit) where a0 + a1 t + a2 t^2 + a3 t^3 reaches 0, or limit when
// there is none (a0 > 0).
double first_cubic_root(double a0, double a1, double a2, double a3, double limit);

}  // namespace spheremap
