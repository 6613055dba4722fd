#include "core/map/stretch_optimizer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/map/vertex_coloring.h"
#include "core/mesh/parallel.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// What a triangle contributes, with its corner weights rotated so that the moving vertex
// is corner 0: N = cp |b - c|^2 + cb |c - p|^2 + cc |p - b|^2.
struct FaceTerm {
  double cp, cb, cc;
  double k1, k2;  // E = k1 N / A^2 + k2 N, A = chord area
};

inline double face_energy(const Vec3& p, const Vec3& b, const Vec3& c, const FaceTerm& f) {
  const double area = 0.5 * triple_product(p, b, c);
  const double n =
      f.cp * squared_norm(b - c) + f.cb * squared_norm(c - p) + f.cc * squared_norm(p - b);
  return f.k1 * n / (area * area) + f.k2 * n;
}

inline Vec3 face_gradient(const Vec3& p, const Vec3& b, const Vec3& c, const FaceTerm& f) {
  const Vec3 bc = cross(b, c);
  const double area = 0.5 * dot(p, bc);
  const double n =
      f.cp * squared_norm(b - c) + f.cb * squared_norm(c - p) + f.cc * squared_norm(p - b);
  const Vec3 grad_n = (2 * f.cb) * (p - c) + (2 * f.cc) * (p - b);
  const Vec3 grad_area = 0.5 * bc;
  return (f.k1 / (area * area) + f.k2) * grad_n - (2 * f.k1 * n / (area * area * area)) * grad_area;
}

struct Incidence {
  uint32_t triangle;
  uint32_t corner;
};

class StretchProblem {
 public:
  StretchProblem(std::span<const Vec3> x, std::span<const Triangle> triangles, size_t n,
                 const StretchOptions& options)
      : triangles_(triangles),
        options_(options),
        weights_(triangles.size()),
        surface_area_(triangles.size()) {
    double total = 0;
    for (size_t t = 0; t < triangles.size(); ++t) {
      const Triangle& tri = triangles[t];
      const Vec3 &a = x[tri[0]], &b = x[tri[1]], &c = x[tri[2]];
      weights_[t] = {dot(b - a, c - a), dot(c - b, a - b), dot(a - c, b - c)};
      surface_area_[t] = 0.5 * norm(cross(b - a, c - a));
      total += surface_area_[t];
    }
    inverse_area_ = surface_area_;
    // The inverse term grows like 1 / surface area: a needle or zero-area triangle (coarse
    // levels of the hierarchy have some) would dominate the whole energy and pull its
    // sphere triangle to nothing against the barrier. Its area is floored at a hundredth
    // of the mean for that term.
    const double floor = 1e-2 * total / static_cast<double>(std::max<size_t>(1, triangles.size()));
    for (double& area : inverse_area_) area = std::max(area, floor);
    surface_total_ = total;

    offsets_.assign(n + 1, 0);
    for (const Triangle& tri : triangles)
      for (uint32_t v : tri) ++offsets_[v + 1];
    for (size_t v = 0; v < n; ++v) offsets_[v + 1] += offsets_[v];
    incidences_.resize(offsets_.back());
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (uint32_t t = 0; t < triangles.size(); ++t)
      for (uint32_t k = 0; k < 3; ++k) incidences_[fill[triangles[t][k]]++] = {t, k};
    classes_ = color_classes(triangles, n);
  }

  const std::vector<std::vector<uint32_t>>& classes() const { return classes_; }

  // Total energy per unit surface area, and the scale s^2 = surface area / chord area.
  double energy(std::span<const Vec3> q) const {
    double sum = 0;
    for (size_t t = 0; t < triangles_.size(); ++t) {
      const Triangle& tri = triangles_[t];
      sum += face_energy(q[tri[0]], q[tri[1]], q[tri[2]], term(t, 0));
    }
    return sum / surface_total_;
  }

  void set_scale(std::span<const Vec3> q) {
    double chord = 0;
    for (const Triangle& tri : triangles_)
      chord += 0.5 * triple_product(q[tri[0]], q[tri[1]], q[tri[2]]);
    scale2_ = surface_total_ / chord;
  }

  // One Newton step of vertex v; returns its move relative to its mean edge length
  // (0 when it stays).
  double move_vertex(std::span<Vec3> q, uint32_t v) const {
    const Vec3 p = q[v];
    const uint32_t begin = offsets_[v], end = offsets_[v + 1];
    // Local scales: mean edge length, and the smallest distance from p to the plane of
    // an opposite edge (sets the difference step far inside the flip-free region).
    double edge_sum = 0, min_height = INFINITY;
    for (uint32_t i = begin; i < end; ++i) {
      const auto [b, c] = opposite(q, incidences_[i]);
      edge_sum += norm(b - p);
      const Vec3 bc = cross(b, c);
      min_height = std::min(min_height, dot(p, bc) / norm(bc));
    }
    const double edge = edge_sum / (end - begin);
    if (!(min_height > 0)) return 0;  // not valid: leave it (the caller guarantees validity)

    auto gradient = [&](const Vec3& at) {
      Vec3 g;
      for (uint32_t i = begin; i < end; ++i) {
        const auto [b, c] = opposite(q, incidences_[i]);
        g += face_gradient(at, b, c, term(incidences_[i]));
      }
      return g;
    };
    auto energy_at = [&](const Vec3& at) {
      double e = 0;
      for (uint32_t i = begin; i < end; ++i) {
        const auto [b, c] = opposite(q, incidences_[i]);
        e += face_energy(at, b, c, term(incidences_[i]));
      }
      return e;
    };

    // Tangent frame at p.
    const Vec3 axis = std::abs(p.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 t1 = normalized_or(cross(p, axis), Vec3{0, 0, 1});
    const Vec3 t2 = cross(p, t1);
    const Vec3 grad = gradient(p);
    const double g1 = dot(grad, t1), g2 = dot(grad, t2);
    const double h = 1e-4 * min_height;
    const Vec3 ga = gradient(p + h * t1), gb = gradient(p + h * t2);
    // Hessian on the sphere: the chart's, less the radial gradient (normalization curves
    // the chart), symmetrized, eigenvalues made positive.
    const double radial = dot(grad, p);
    double h11 = (dot(ga, t1) - g1) / h - radial;
    double h22 = (dot(gb, t2) - g2) / h - radial;
    double h12 = 0.5 * ((dot(ga, t2) - g2) / h + (dot(gb, t1) - g1) / h);
    const double mean = 0.5 * (h11 + h22);
    const double root = std::sqrt(std::max(0.0, 0.25 * (h11 - h22) * (h11 - h22) + h12 * h12));
    double l1 = mean + root, l2 = mean - root;
    const double largest = std::max(std::abs(l1), std::abs(l2));
    if (!(largest > 0) || !std::isfinite(largest)) return 0;
    l1 = std::max(std::abs(l1), 1e-8 * largest), l2 = std::max(std::abs(l2), 1e-8 * largest);
    // Eigenvector of the first eigenvalue.
    double ex = h12, ey = l1 - h11;
    if (std::abs(ex) + std::abs(ey) < 1e-300 * largest) ex = 1, ey = 0;
    if (root == 0) ex = 1, ey = 0;
    const double elen = std::hypot(ex, ey);
    ex /= elen, ey /= elen;
    // d = -H^-1 g with H = l1 e e^T + l2 e_perp e_perp^T.
    const double ge = g1 * ex + g2 * ey, gp = -g1 * ey + g2 * ex;
    const double de = -ge / l1, dp = -gp / l2;
    const double d1 = de * ex - dp * ey, d2 = de * ey + dp * ex;
    const double slope = g1 * d1 + g2 * d2;
    if (!(slope < 0)) return 0;
    const Vec3 direction = d1 * t1 + d2 * t2;

    // Largest flip-free step: det[p + t d, b, c] = det[p, b, c] + t d.(b x c).
    double limit = INFINITY;
    for (uint32_t i = begin; i < end; ++i) {
      const auto [b, c] = opposite(q, incidences_[i]);
      const Vec3 bc = cross(b, c);
      const double rate = dot(direction, bc);
      if (rate < 0) limit = std::min(limit, 0.8 * dot(p, bc) / -rate);
    }
    const double e0 = energy_at(p);
    auto try_step = [&](double t, double& energy) {
      const Vec3 candidate = normalized_or(p + t * direction, p);
      for (uint32_t i = begin; i < end; ++i) {
        const auto [b, c] = opposite(q, incidences_[i]);
        if (!is_valid_triangle(candidate, b, c)) return false;
      }
      energy = energy_at(candidate);
      return std::isfinite(energy);
    };
    // Armijo backtracking from the Newton step; steps below 1e-6 of the smallest height
    // move nothing measurable.
    double step = std::min(1.0, limit), energy = e0;
    bool accepted = false;
    for (int halving = 0; halving < 16 && !accepted; ++halving, step *= 0.5) {
      if (step * norm(direction) < 1e-6 * min_height) return 0;
      accepted = try_step(step, energy) && energy <= e0 + 1e-4 * step * slope;
      if (accepted) break;
    }
    if (!accepted) return 0;
    // Near a squeezed triangle the energy is like 1 / area^2, where a Newton step only
    // grows the area by a third: double the step while that still lowers the energy.
    for (int doubling = 0; doubling < 20 && step < limit; ++doubling) {
      const double longer = std::min(2 * step, limit);
      double longer_energy;
      if (!try_step(longer, longer_energy) || !(longer_energy < energy)) break;
      step = longer, energy = longer_energy;
    }
    const Vec3 moved = normalized_or(p + step * direction, p);
    q[v] = moved;
    return norm(moved - p) / std::min(edge, min_height);
  }

  // Vertices adjacent through a triangle, for the active set.
  template <class Visit>
  void for_each_neighbor(uint32_t v, Visit&& visit) const {
    for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i) {
      const Triangle& tri = triangles_[incidences_[i].triangle];
      visit(tri[(incidences_[i].corner + 1) % 3]);
    }
  }

 private:
  std::pair<const Vec3&, const Vec3&> opposite(std::span<const Vec3> q, Incidence i) const {
    const Triangle& tri = triangles_[i.triangle];
    return {q[tri[(i.corner + 1) % 3]], q[tri[(i.corner + 2) % 3]]};
  }
  FaceTerm term(Incidence i) const { return term(i.triangle, i.corner); }
  FaceTerm term(size_t t, uint32_t corner) const {
    const auto& w = weights_[t];
    return {w[corner], w[(corner + 1) % 3], w[(corner + 2) % 3], surface_area_[t] / (8 * scale2_),
            options_.lambda * scale2_ / (8 * inverse_area_[t])};
  }

  std::span<const Triangle> triangles_;
  const StretchOptions& options_;
  std::vector<std::array<double, 3>> weights_;
  std::vector<double> surface_area_, inverse_area_;
  double surface_total_ = 0;
  double scale2_ = 1;
  std::vector<uint32_t> offsets_;
  std::vector<Incidence> incidences_;
  std::vector<std::vector<uint32_t>> classes_;
};

}  // namespace

StretchStats optimize_stretch(std::span<const Vec3> x, std::span<const Triangle> triangles,
                              std::span<Vec3> q, const StretchOptions& options,
                              const std::function<bool()>& should_stop) {
  StretchStats stats;
  const size_t n = q.size();
  StretchProblem problem(x, triangles, n, options);
  const int threads = resolve_threads(options.threads);
  std::vector<double> moved(n, 0);
  std::vector<char> active(n, 1);
  double previous = INFINITY;
  for (; stats.sweeps < options.max_sweeps; ++stats.sweeps) {
    problem.set_scale(q);
    const double energy = problem.energy(q);
    if (stats.sweeps == 0) stats.initial_energy = energy;
    if (previous - energy < options.relative_decrease * energy) break;
    previous = energy;
    size_t updates = 0;
    for (const std::vector<uint32_t>& members : problem.classes()) {
      if (should_stop()) {
        stats.final_energy = problem.energy(q);
        return stats;
      }
      const long long count = static_cast<long long>(members.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) reduction(+ : updates) if (count >= 512)
      for (long long k = 0; k < count; ++k) {
        const uint32_t v = members[static_cast<size_t>(k)];
        if (!active[v]) {
          moved[v] = 0;
          continue;
        }
        moved[v] = problem.move_vertex(q, v);
        ++updates;
      }
    }
    stats.vertex_updates += static_cast<double>(updates);
    // A vertex stays active while it or a neighbour still moves.
    size_t still = 0;
    for (uint32_t v = 0; v < n; ++v) {
      bool keep = moved[v] > options.active_tolerance;
      problem.for_each_neighbor(
          v, [&](uint32_t w) { keep = keep || moved[w] > options.active_tolerance; });
      active[v] = keep;
      still += keep;
    }
    if (still == 0) {
      ++stats.sweeps;
      break;
    }
  }
  problem.set_scale(q);
  stats.final_energy = problem.energy(q);
  return stats;
}

}  // namespace spheremap
