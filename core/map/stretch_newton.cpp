#include "core/map/stretch_newton.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d to_eigen(const Vec3& a) {
  return {a.x, a.y, a.z};
}

Eigen::Matrix3d cross_matrix(const Vec3& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z, a.y, a.z, 0, -a.x, -a.y, a.x, 0;
  return m;
}

// The energy's three sums over the triangles: stretch N / A^2, inverse N, and A; +inf
// when a triangle is not valid. Fixed chunks summed in order, so the result does not
// depend on the thread count.
double total_energy(std::span<const Triangle> triangles, std::span<const TriangleEnergy> energy,
                    double surface_area, std::span<const Vec3> q, int threads) {
  constexpr size_t kChunk = 4096;
  const size_t chunks = (triangles.size() + kChunk - 1) / kChunk;
  std::vector<std::array<double, 3>> partial(chunks);
  parallel_for(chunks, threads, [&](size_t k) {
    std::array<double, 3> sum{0, 0, 0};
    for (size_t t = k * kChunk; t < std::min(triangles.size(), (k + 1) * kChunk); ++t) {
      const Vec3 &p = q[triangles[t][0]], &b = q[triangles[t][1]], &c = q[triangles[t][2]];
      if (!is_valid_triangle(p, b, c)) {
        sum[0] = INFINITY;
        break;
      }
      const TriangleEnergy& e = energy[t];
      const double area = 0.5 * triple_product(p, b, c);
      const double n = e.c[0] * squared_norm(b - c) + e.c[1] * squared_norm(c - p) +
                       e.c[2] * squared_norm(p - b);
      sum[0] += e.stretch * n / (area * area);
      sum[1] += e.inverse * n;
      sum[2] += area;
    }
    partial[k] = sum;
  });
  std::array<double, 3> total{0, 0, 0};
  for (const auto& part : partial)
    for (int i = 0; i < 3; ++i) total[i] += part[i];
  const double scale2 = surface_area / total[2];
  return total[0] / scale2 + total[1] * scale2;
}

// s^2 for the map q.
double scale_squared(std::span<const Triangle> triangles, double surface_area,
                     std::span<const Vec3> q) {
  double sum = 0;
  for (const Triangle& t : triangles) sum += 0.5 * triple_product(q[t[0]], q[t[1]], q[t[2]]);
  return surface_area / sum;
}

// One triangle's gradient and positive semi-definite Hessian in the tangent coordinates
// of its corners, s^2 held fixed (k1 = stretch / s^2, k2 = inverse s^2). Ambient first:
// with A = det / 2 (gradient a, Hessian of the triple product) and N quadratic,
//   grad E = s grad N - 2 k1 N / A^3 a,   s = k1 / A^2 + k2
//   hess E = s hess N - 2 k1 / A^3 (grad N a^T + a grad N^T) + 6 k1 N / A^4 a a^T
//            - 2 k1 N / A^3 hess A
// then restricted to the frames, less each corner's radial gradient (renormalizing curves
// the chart), and its negative eigenvalues clamped.
void triangle_newton_terms(const std::array<Vec3, 3>& corner,
                           const std::array<std::array<Vec3, 2>, 3>& frames,
                           const TriangleEnergy& e, double scale2, Vec6& gradient, Mat6& hessian) {
  const double k1 = e.stretch / scale2, k2 = e.inverse * scale2;
  const double area = 0.5 * triple_product(corner[0], corner[1], corner[2]);
  double n = 0;
  Vec9 grad_n, grad_a;
  Mat9 hess_n = Mat9::Zero(), hess_a = Mat9::Zero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    n += e.c[i] * squared_norm(corner[j] - corner[k]);
    grad_n.segment<3>(3 * i) =
        to_eigen(2 * e.c[k] * (corner[i] - corner[j]) + 2 * e.c[j] * (corner[i] - corner[k]));
    grad_a.segment<3>(3 * i) = to_eigen(0.5 * cross(corner[j], corner[k]));
    const Eigen::Matrix3d w = 2 * e.c[i] * Eigen::Matrix3d::Identity();  // edge (j, k)
    hess_n.block<3, 3>(3 * j, 3 * j) += w;
    hess_n.block<3, 3>(3 * k, 3 * k) += w;
    hess_n.block<3, 3>(3 * j, 3 * k) -= w;
    hess_n.block<3, 3>(3 * k, 3 * j) -= w;
    // A = q_i . (q_j x q_k) / 2, so d2A / dq_j dq_k = -[q_i]x / 2.
    hess_a.block<3, 3>(3 * j, 3 * k) = -0.5 * cross_matrix(corner[i]);
    hess_a.block<3, 3>(3 * k, 3 * j) = 0.5 * cross_matrix(corner[i]);
  }
  const double inv = 1 / area, inv2 = inv * inv;
  const double s = k1 * inv2 + k2;
  const Vec9 grad = s * grad_n - (2 * k1 * n * inv2 * inv) * grad_a;
  const Mat9 hess =
      s * hess_n -
      (2 * k1 * inv2 * inv) * (grad_n * grad_a.transpose() + grad_a * grad_n.transpose()) +
      (6 * k1 * n * inv2 * inv2) * grad_a * grad_a.transpose() - (2 * k1 * n * inv2 * inv) * hess_a;
  Eigen::Matrix<double, 9, 6> frame = Eigen::Matrix<double, 9, 6>::Zero();
  for (int i = 0; i < 3; ++i) {
    frame.block<3, 1>(3 * i, 2 * i) = to_eigen(frames[i][0]);
    frame.block<3, 1>(3 * i, 2 * i + 1) = to_eigen(frames[i][1]);
  }
  Mat6 h = frame.transpose() * hess * frame;
  for (int i = 0; i < 3; ++i) {
    const double radial = grad.segment<3>(3 * i).dot(to_eigen(corner[i]));
    h(2 * i, 2 * i) -= radial, h(2 * i + 1, 2 * i + 1) -= radial;
  }
  const Eigen::SelfAdjointEigenSolver<Mat6> eigen(h);
  Vec6 values = eigen.eigenvalues();
  const double largest = std::max(1e-300, values.cwiseAbs().maxCoeff());
  for (int i = 0; i < 6; ++i) values(i) = std::max(values(i), 1e-8 * largest);
  hessian = eigen.eigenvectors() * values.asDiagonal() * eigen.eigenvectors().transpose();
  gradient = frame.transpose() * grad;
}

// The Newton direction per vertex (ambient, tangent) and the directional derivative of
// the energy along it; slope >= 0 when there is no descent direction.
struct Direction {
  std::vector<Vec3> d;
  double slope = 0;
};

Direction newton_direction(std::span<const Triangle> triangles,
                           std::span<const TriangleEnergy> energy, double surface_area,
                           std::span<const Vec3> q, int threads) {
  const size_t n = q.size(), m = triangles.size();
  const double scale2 = scale_squared(triangles, surface_area, q);
  std::vector<std::array<Vec3, 2>> frames(n);
  parallel_for(n, threads, [&](size_t v) { frames[v] = tangent_frame(q[v]); });
  std::vector<Vec6> gradients(m);
  std::vector<Mat6> hessians(m);
  parallel_for(m, threads, [&](size_t t) {
    const Triangle& tri = triangles[t];
    triangle_newton_terms({q[tri[0]], q[tri[1]], q[tri[2]]},
                          {frames[tri[0]], frames[tri[1]], frames[tri[2]]}, energy[t], scale2,
                          gradients[t], hessians[t]);
  });
  const auto unknowns = static_cast<Eigen::Index>(2 * n);
  auto row = [&](const Triangle& tri, int a) {
    return 2 * static_cast<Eigen::Index>(tri[a / 2]) + a % 2;
  };
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns), diagonal = rhs;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(36 * m + 2 * n);
  for (size_t t = 0; t < m; ++t)
    for (int a = 0; a < 6; ++a) {
      rhs(row(triangles[t], a)) -= gradients[t](a);
      diagonal(row(triangles[t], a)) += hessians[t](a, a);
      for (int b = 0; b < 6; ++b)
        entries.emplace_back(row(triangles[t], a), row(triangles[t], b), hessians[t](a, b));
    }
  // Clamped eigenvalues leave the sum semi-definite at worst: a relative shift makes it
  // definite without changing the step measurably.
  for (Eigen::Index r = 0; r < unknowns; ++r) entries.emplace_back(r, r, 1e-8 * diagonal(r));
  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(matrix);
  Direction out;
  if (solver.info() != Eigen::Success) return out;
  const Eigen::VectorXd step = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !step.allFinite()) return out;
  out.d.resize(n);
  for (size_t v = 0; v < n; ++v) {
    const auto r = 2 * static_cast<Eigen::Index>(v);
    out.d[v] = step(r) * frames[v][0] + step(r + 1) * frames[v][1];
  }
  out.slope = -step.dot(rhs);
  return out;
}

// The largest t <= limit for which every triangle stays valid along q + t d (positive
// scaling, as the renormalization, keeps each determinant's sign).
double flip_free_limit(std::span<const Triangle> triangles, std::span<const Vec3> q,
                       std::span<const Vec3> d, double limit) {
  for (const Triangle& tri : triangles) {
    const Vec3 &p = q[tri[0]], &b = q[tri[1]], &c = q[tri[2]];
    const Vec3 &dp = d[tri[0]], &db = d[tri[1]], &dc = d[tri[2]];
    const double a1 =
        triple_product(dp, b, c) + triple_product(p, db, c) + triple_product(p, b, dc);
    const double a2 =
        triple_product(dp, db, c) + triple_product(dp, b, dc) + triple_product(p, db, dc);
    limit = first_cubic_root(triple_product(p, b, c), a1, a2, triple_product(dp, db, dc), limit);
  }
  return limit;
}

}  // namespace

double first_cubic_root(double a0, double a1, double a2, double a3, double limit) {
  auto f = [&](double t) { return a0 + t * (a1 + t * (a2 + t * a3)); };
  // f is monotone between the roots of f' = a1 + 2 a2 t + 3 a3 t^2: look for a sign
  // change on each piece, in order, and bisect the first.
  std::array<double, 4> cuts{0, limit, limit, limit};
  size_t count = 1;
  auto add = [&](double t) {
    if (t > 0 && t < limit) cuts[count++] = t;
  };
  if (a3 != 0) {
    const double disc = 4 * a2 * a2 - 12 * a3 * a1;
    if (disc >= 0) {
      const double r = std::sqrt(disc);
      const double t1 = (-2 * a2 - r) / (6 * a3), t2 = (-2 * a2 + r) / (6 * a3);
      add(std::min(t1, t2));  // ascending, so no sort
      add(std::max(t1, t2));
    }
  } else if (a2 != 0) {
    add(-a1 / (2 * a2));
  }
  cuts[count++] = limit;
  for (size_t k = 0; k + 1 < count; ++k) {
    double lo = cuts[k], hi = cuts[k + 1];
    if (f(hi) > 0) continue;
    for (int it = 0; it < 64; ++it) {
      const double mid = 0.5 * (lo + hi);
      (f(mid) > 0 ? lo : hi) = mid;
    }
    return lo;
  }
  return limit;
}

double newton_step(std::span<const Triangle> triangles, std::span<const TriangleEnergy> energy,
                   double surface_area, std::span<Vec3> q, int threads) {
  const Direction direction = newton_direction(triangles, energy, surface_area, q, threads);
  if (!(direction.slope < 0)) return 0;
  const double e0 = total_energy(triangles, energy, surface_area, q, threads);
  if (!std::isfinite(e0) || !(e0 > 0)) return 0;
  const double limit = flip_free_limit(triangles, q, direction.d, 1.25);
  const size_t n = q.size();
  std::vector<Vec3> candidate(n);
  for (double step = 0.8 * limit; step > 1e-10; step *= 0.5) {
    parallel_for(n, threads, [&](size_t v) {
      candidate[v] = normalized_or(q[v] + step * direction.d[v], q[v]);
    });
    const double e = total_energy(triangles, energy, surface_area, candidate, threads);
    if (e <= e0 + 1e-4 * step * direction.slope) {
      std::copy(candidate.begin(), candidate.end(), q.begin());
      return (e0 - e) / e0;
    }
  }
  return 0;
}

}  // namespace spheremap
