#include "core/map/stretch_optimizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/map/map_check.h"
#include "core/map/stretch_newton.h"
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

// One triangle of a moving vertex's star: the other corners b, c (in order), b x c, and
// the triangle's energy terms with the moving vertex as corner 0.
struct StarFace {
  Vec3 b, c, bc;
  double bc_length2;  // |c - b|^2
  FaceTerm term;
};

// is_valid_triangle(p, f.b, f.c) with b x c already known: the common case (a clear
// margin) decided from it, the rest by the robust test itself. Corners on the unit sphere
// are at most 2 apart, so a determinant above 1e-10 x 4.01 clears the margin of any of
// its edges without their lengths (the same answers, a third of the test's work).
inline bool valid_with(const Vec3& p, const StarFace& f) {
  const double det = dot(p, f.bc);
  if (det > 4.01e-10 + 1e-14) return true;
  const double longest = std::max({squared_norm(f.b - p), squared_norm(f.c - p), f.bc_length2});
  if (det > 1e-10 * longest + 1e-14) return true;
  return is_valid_triangle(p, f.b, f.c);
}

struct Incidence {
  uint32_t triangle;
  uint32_t corner;
};

// An incidence packed in 4 bytes, 3 triangle + corner (the star lists are a sixth of the
// optimizer's memory at 17M triangles). StretchProblem refuses more than 2^32 / 3 triangles.
inline uint32_t packed(uint32_t triangle, uint32_t corner) {
  return 3 * triangle + corner;
}
inline Incidence unpacked(uint32_t incidence) {
  return {incidence / 3, incidence % 3};
}

class StretchProblem {
 public:
  StretchProblem(std::span<const Vec3> x, std::span<const Triangle> triangles, size_t n,
                 const StretchOptions& options, std::span<const double> area_scale)
      : triangles_(triangles),
        options_(options),
        weights_(triangles.size()),
        surface_area_(triangles.size()) {
    if (triangles.size() > std::numeric_limits<uint32_t>::max() / 3)
      throw std::length_error("stretch optimizer: over 2^32 / 3 triangles");
    double total = 0;
    for (size_t t = 0; t < triangles.size(); ++t) {
      const Triangle& tri = triangles[t];
      const Vec3 &a = x[tri[0]], &b = x[tri[1]], &c = x[tri[2]];
      // Scaling a triangle's area by r keeps its shape and scales every weight by r.
      const double r = area_scale.empty() ? 1.0 : area_scale[t];
      weights_[t] = {r * dot(b - a, c - a), r * dot(c - b, a - b), r * dot(a - c, b - c)};
      surface_area_[t] = r * 0.5 * norm(cross(b - a, c - a));
      total += surface_area_[t];
    }
    // The inverse term grows like 1 / surface area: a needle or zero-area triangle (coarse
    // levels of the hierarchy have some) would dominate the whole energy and pull its
    // sphere triangle to nothing against the barrier. Its area is floored at a hundredth
    // of the mean for that term (inverse_area; the triangles raised below stay under it).
    const double mean = total / static_cast<double>(std::max<size_t>(1, triangles.size()));
    inverse_area_floor_ = 1e-2 * mean;
    // A (nearly) zero-area surface triangle (CAD slivers, collinear corners) would have no
    // stretch term at all, so nothing would keep its sphere triangle from collapsing to a
    // degenerate one. It counts as a small equilateral triangle instead: area 1e-4 of the
    // mean, corner weights c_i = 2 area / sqrt(3).
    for (size_t t = 0; t < triangles.size(); ++t)
      if (!(surface_area_[t] >= 1e-4 * mean)) {
        surface_area_[t] = 1e-4 * mean;
        const double c = 2 * surface_area_[t] / std::sqrt(3.0);
        weights_[t] = {c, c, c};
      }
    surface_total_ = total;

    offsets_.assign(n + 1, 0);
    for (const Triangle& tri : triangles)
      for (uint32_t v : tri) ++offsets_[v + 1];
    for (size_t v = 0; v < n; ++v) offsets_[v + 1] += offsets_[v];
    incidences_.resize(offsets_.back());
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (uint32_t t = 0; t < triangles.size(); ++t)
      for (uint32_t k = 0; k < 3; ++k) incidences_[fill[triangles[t][k]]++] = packed(t, k);
    classes_ = color_classes(n, [&](uint32_t v, auto&& visit) {
      for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i) {
        const Incidence incidence = unpacked(incidences_[i]);
        const Triangle& tri = triangles_[incidence.triangle];
        visit(tri[(incidence.corner + 1) % 3]);
        visit(tri[(incidence.corner + 2) % 3]);
      }
    });
  }

  const std::vector<std::vector<uint32_t>>& classes() const { return classes_; }

  // Sets the scale s^2 = surface area / sum of det / 2 for the map q, and returns the
  // total energy per unit surface area there. One pass, in parallel over fixed chunks
  // summed in order, so the result does not depend on the thread count.
  double rescale(std::span<const Vec3> q, int threads) {
    constexpr size_t kChunk = 4096;
    const size_t chunks = (triangles_.size() + kChunk - 1) / kChunk;
    std::vector<std::array<double, 3>> partial(chunks);  // chord, stretch / s^-2, inverse / s^2
    // In parallel from 8 chunks (32,768 triangles; parallel_for's threshold counts items
    // and left it serial below 33M): a pass per sweep was 5% of a 4.3M-triangle map's
    // samples, on one core, and 3% of horse's (97K triangles, under the 64 chunks first
    // chosen; its optimization 0.217 -> 0.205 s on 2 cores at 8).
    const long long count = static_cast<long long>(chunks);
#pragma omp parallel for schedule(static) num_threads(threads) if (chunks >= 8)
    for (long long chunk = 0; chunk < count; ++chunk) {
      const auto k = static_cast<size_t>(chunk);
      std::array<double, 3> sum{0, 0, 0};
      for (size_t t = k * kChunk; t < std::min(triangles_.size(), (k + 1) * kChunk); ++t) {
        const Triangle& tri = triangles_[t];
        const Vec3 &p = q[tri[0]], &b = q[tri[1]], &c = q[tri[2]];
        const auto& w = weights_[t];
        const double area = 0.5 * triple_product(p, b, c);
        const double n =
            w[0] * squared_norm(b - c) + w[1] * squared_norm(c - p) + w[2] * squared_norm(p - b);
        sum[0] += area;
        sum[1] += surface_area_[t] * n / (8 * area * area);
        sum[2] += options_.lambda * n / (8 * inverse_area(t));
      }
      partial[k] = sum;
    }
    std::array<double, 3> total{0, 0, 0};
    for (const auto& part : partial)
      for (int i = 0; i < 3; ++i) total[i] += part[i];
    scale2_ = surface_total_ / total[0];
    return (total[1] / scale2_ + total[2] * scale2_) / surface_total_;
  }

  // One Newton step of vertex v; returns its move relative to its smallest height (0 when
  // it stays).
  double move_vertex(std::span<Vec3> q, uint32_t v) const {
    const Vec3 p = q[v];
    // The star, gathered once: opposite corners, b x c, and the face's energy terms.
    thread_local std::vector<StarFace> star;
    star.clear();
    for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i) {
      const Incidence incidence = unpacked(incidences_[i]);
      const auto [b, c] = opposite(q, incidence);
      star.push_back({b, c, cross(b, c), squared_norm(c - b), term(incidence)});
    }
    // Local scale: the smallest distance from p to the plane (through the centre) of an
    // opposite edge; moves are measured against it.
    double min_height2 = INFINITY;
    for (const StarFace& f : star) {
      const double det = dot(p, f.bc);
      if (!(det > 0)) return 0;  // not valid: leave it (the caller guarantees validity)
      min_height2 = std::min(min_height2, det * det / squared_norm(f.bc));
    }
    const double min_height = std::sqrt(min_height2);

    auto energy_at = [&](const Vec3& at) {
      double e = 0;
      for (const StarFace& f : star) {
        const double area = 0.5 * dot(at, f.bc);
        const double n = f.term.cp * f.bc_length2 + f.term.cb * squared_norm(f.c - at) +
                         f.term.cc * squared_norm(at - f.b);
        e += f.term.k1 * n / (area * area) + f.term.k2 * n;
      }
      return e;
    };

    // Gradient and Hessian in the tangent frame (t1, t2) at p, analytic. Per face, with
    // A = p.(b x c) / 2 (linear in p, gradient a = b x c / 2) and N quadratic (Hessian
    // 2 (cb + cc) I):
    //   grad E = (k1 / A^2 + k2) grad N - 2 k1 N / A^3 a
    //   hess E = (k1 / A^2 + k2) 2 (cb + cc) I - 2 k1 / A^3 (grad N a^T + a grad N^T)
    //            + 6 k1 N / A^4 a a^T
    const auto [t1, t2] = tangent_frame(p);
    Vec3 grad;
    double h11 = 0, h12 = 0, h22 = 0, e0 = 0;
    for (const StarFace& face : star) {
      const Vec3 &b = face.b, &c = face.c;
      const FaceTerm& f = face.term;
      const Vec3 a = 0.5 * face.bc;
      const double area = dot(p, a);
      const double n =
          f.cp * face.bc_length2 + f.cb * squared_norm(c - p) + f.cc * squared_norm(p - b);
      const Vec3 grad_n = (2 * f.cb) * (p - c) + (2 * f.cc) * (p - b);
      const double inv = 1 / area, inv2 = inv * inv;
      const double scale = f.k1 * inv2 + f.k2;
      e0 += scale * n;
      grad += scale * grad_n - (2 * f.k1 * n * inv2 * inv) * a;
      const double n1 = dot(grad_n, t1), n2 = dot(grad_n, t2);
      const double a1 = dot(a, t1), a2 = dot(a, t2);
      const double identity = scale * 2 * (f.cb + f.cc);
      const double cross_term = 2 * f.k1 * inv2 * inv, outer = 6 * f.k1 * n * inv2 * inv2;
      h11 += identity - cross_term * 2 * n1 * a1 + outer * a1 * a1;
      h22 += identity - cross_term * 2 * n2 * a2 + outer * a2 * a2;
      h12 += -cross_term * (n1 * a2 + a1 * n2) + outer * a1 * a2;
    }
    const double g1 = dot(grad, t1), g2 = dot(grad, t2);
    // On the sphere: the chart's Hessian less the radial gradient (normalization curves
    // the chart); eigenvalues made positive.
    const double radial = dot(grad, p);
    h11 -= radial, h22 -= radial;
    const double mean = 0.5 * (h11 + h22);
    const double root = std::sqrt(std::max(0.0, 0.25 * (h11 - h22) * (h11 - h22) + h12 * h12));
    const double e1 = mean + root, e2 = mean - root;
    const double largest = std::max(std::abs(e1), std::abs(e2));
    if (!(largest > 0) || !std::isfinite(largest)) return 0;
    const double l1 = std::max(std::abs(e1), 1e-8 * largest);
    const double l2 = std::max(std::abs(e2), 1e-8 * largest);
    // Unit eigenvector of e1 (any direction when the Hessian is a multiple of I).
    double ex = 1, ey = 0;
    if (root > 1e-12 * largest) {
      ex = h12, ey = e1 - h11;
      if (std::abs(ex) + std::abs(ey) < 1e-12 * largest) ex = e1 - h22, ey = h12;
      const double length = std::sqrt(ex * ex + ey * ey);
      ex /= length, ey /= length;
    }
    // d = -H^-1 g with H = l1 e e^T + l2 e_perp e_perp^T.
    const double ge = g1 * ex + g2 * ey, gp = -g1 * ey + g2 * ex;
    const double de = -ge / l1, dp = -gp / l2;
    const double d1 = de * ex - dp * ey, d2 = de * ey + dp * ex;
    const double slope = g1 * d1 + g2 * d2;
    if (!(slope < 0)) return 0;
    const Vec3 direction = d1 * t1 + d2 * t2;

    // Largest flip-free step: det[p + t d, b, c] = det[p, b, c] + t d.(b x c).
    double limit = INFINITY;
    for (const StarFace& f : star) {
      const double rate = dot(direction, f.bc);
      if (rate < 0) limit = std::min(limit, 0.8 * dot(p, f.bc) / -rate);
    }
    auto try_step = [&](double t, double& energy) {
      const Vec3 candidate = normalized_or(p + t * direction, p);
      for (const StarFace& f : star)
        if (!valid_with(candidate, f)) return false;
      energy = energy_at(candidate);
      return std::isfinite(energy);
    };
    // Over-relaxed first (StretchOptions::over_relaxation), then Armijo backtracking from
    // the Newton step; steps below 1e-6 of the smallest height move nothing measurable.
    auto armijo = [&](double t, double& energy) {
      return try_step(t, energy) && energy <= e0 + 1e-4 * t * slope;
    };
    double step = std::min(options_.over_relaxation, limit), energy = e0;
    bool accepted = step > 1 && armijo(step, energy);
    if (!accepted) step = std::min(1.0, limit);
    for (int halving = 0; halving < 16 && !accepted; ++halving, step *= 0.5) {
      if (step * norm(direction) < 1e-6 * min_height) return 0;
      accepted = armijo(step, energy);
      if (accepted) break;
    }
    if (!accepted) return 0;
    // Near a squeezed triangle the energy is like 1 / area^2, where a Newton step only
    // grows the area by a third: double the step while that still lowers the energy.
    // Only tried when the step did better than the quadratic model foresaw (it predicts
    // a drop of -slope t (1 - t / 2)): elsewhere the model is right and doubling would
    // only cost energy evaluations (measured: a fifth of the optimizer's time).
    const bool model_too_pessimistic = e0 - energy > -slope * step * (1 - step / 2) * 1.5;
    for (int doubling = 0; model_too_pessimistic && doubling < 20 && step < limit; ++doubling) {
      const double longer = std::min(2 * step, limit);
      double longer_energy;
      if (!try_step(longer, longer_energy) || !(longer_energy < energy)) break;
      step = longer, energy = longer_energy;
    }
    const Vec3 moved = normalized_or(p + step * direction, p);
    q[v] = moved;
    return norm(moved - p) / min_height;
  }

  // Triangle t's energy per unit of its surface area in q (after rescale); infinite
  // when it is not valid.
  double density(std::span<const Vec3> q, uint32_t t) const {
    const Triangle& tri = triangles_[t];
    const Vec3 &p = q[tri[0]], &b = q[tri[1]], &c = q[tri[2]];
    const double area = 0.5 * triple_product(p, b, c);
    if (!(area > 0)) return INFINITY;
    const FaceTerm f = term(t, 0);
    const double n =
        f.cp * squared_norm(b - c) + f.cb * squared_norm(c - p) + f.cc * squared_norm(p - b);
    return (f.k1 * n / (area * area) + f.k2 * n) / surface_area_[t];
  }

  // Whether a triangle of v's star has a density above `threshold`.
  bool in_hot_star(std::span<const Vec3> q, uint32_t v, double threshold) const {
    for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i)
      if (density(q, unpacked(incidences_[i]).triangle) > threshold) return true;
    return false;
  }

  size_t triangle_count() const {
    return triangles_.size();
  }
  std::span<const Triangle> triangles() const {
    return triangles_;
  }

  double surface_total() const {
    return surface_total_;
  }

  // Every triangle's energy terms without the scale, for a whole-map Newton step.
  std::vector<TriangleEnergy> triangle_energies() const {
    std::vector<TriangleEnergy> out(triangles_.size());
    for (size_t t = 0; t < triangles_.size(); ++t) {
      const auto& w = weights_[t];
      out[t] = {{w[0], w[1], w[2]}, surface_area_[t] / 8, options_.lambda / (8 * inverse_area(t))};
    }
    return out;
  }

  // Vertices adjacent through a triangle, for the active set.
  template <class Visit>
  void for_each_neighbor(uint32_t v, Visit&& visit) const {
    for (uint32_t i = offsets_[v]; i < offsets_[v + 1]; ++i) {
      const Incidence incidence = unpacked(incidences_[i]);
      visit(triangles_[incidence.triangle][(incidence.corner + 1) % 3]);
    }
  }

 private:
  std::pair<const Vec3&, const Vec3&> opposite(std::span<const Vec3> q, Incidence i) const {
    const Triangle& tri = triangles_[i.triangle];
    return {q[tri[(i.corner + 1) % 3]], q[tri[(i.corner + 2) % 3]]};
  }
  FaceTerm term(Incidence i) const {
    return term(i.triangle, i.corner);
  }
  FaceTerm term(size_t t, uint32_t corner) const {
    const auto& w = weights_[t];
    return {w[corner], w[(corner + 1) % 3], w[(corner + 2) % 3], surface_area_[t] / (8 * scale2_),
            options_.lambda * scale2_ / (8 * inverse_area(t))};
  }

  std::span<const Triangle> triangles_;
  const StretchOptions& options_;
  std::vector<std::array<double, 3>> weights_;
  // The area of triangle t in the inverse term: its surface area, floored.
  double inverse_area(size_t t) const {
    return std::max(surface_area_[t], inverse_area_floor_);
  }

  std::vector<double> surface_area_;
  double inverse_area_floor_ = 0;
  double surface_total_ = 0;
  double scale2_ = 1;
  std::vector<uint32_t> offsets_;
  std::vector<uint32_t> incidences_;  // packed(triangle, corner), by vertex
  std::vector<std::vector<uint32_t>> classes_;
};

// Insertions leave a few vertices squeezed against their rings: their triangles' energy
// is orders of magnitude above the rest (horse, finest level: 194,939 per unit area
// against 3.0 once optimized), and whole-mesh sweeps spent 13 of their 23 passes bringing
// the total down from there, each pass opening those triangles by a few times only.
// This moves just the vertices of such hot triangles (density over kHotFactor x the
// median), again and again, until none is hot or the hot ones stop moving: the same
// Newton steps, on a few percent of the vertices (horse, finest level: 0.33 updates per
// vertex, and 12 sweeps after it instead of 23). Returns the vertex updates made.
constexpr double kHotFactor = 16;
constexpr size_t kMaxHotPasses = 200;

// The median of the triangles' densities. Its own function so that the densities (8 bytes
// per triangle) are gone before the passes allocate theirs: at the finest level of a
// 17M-triangle map this is where the whole map's memory peaks.
double median_density(const StretchProblem& problem, std::span<const Vec3> q, int threads) {
  const size_t triangles = problem.triangle_count();
  std::vector<double> densities(triangles);
  parallel_for(triangles, threads,
               [&](size_t t) { densities[t] = problem.density(q, static_cast<uint32_t>(t)); });
  std::nth_element(densities.begin(),
                   densities.begin() + static_cast<std::ptrdiff_t>(triangles / 2), densities.end());
  return densities[triangles / 2];
}

double relieve_hot_spots(StretchProblem& problem, std::span<Vec3> q, int threads, double tolerance,
                         const std::function<bool()>& should_stop) {
  const size_t n = q.size();
  const auto triangles = static_cast<uint32_t>(problem.triangle_count());
  if (triangles == 0) return 0;
  const double threshold = kHotFactor * median_density(problem, q, threads);
  if (!std::isfinite(threshold)) return 0;

  // Which vertices are hot, found in parallel (each writes its own flag; the lists are
  // then made in order: the same lists for any thread count). Serial, these scans were
  // a tenth of a 4.3M-triangle map's samples.
  std::vector<char> hot(n, 0);
  std::vector<double> moved(n, 0);
  std::vector<uint32_t> hot_list;
  parallel_for(n, threads, [&](size_t v) {
    hot[v] = problem.in_hot_star(q, static_cast<uint32_t>(v), threshold) ? 1 : 0;
  });
  for (uint32_t v = 0; v < n; ++v)
    if (hot[v]) hot_list.push_back(v);
  double updates = 0;
  std::vector<char> seen(n, 0);
  std::vector<uint32_t> candidates;
  // A pass visits the hot vertices only (a few percent), grouped by colour.
  std::vector<uint32_t> colour(n, 0);
  for (uint32_t c = 0; c < problem.classes().size(); ++c)
    for (uint32_t v : problem.classes()[c]) colour[v] = c;
  std::vector<std::vector<uint32_t>> hot_by_colour(problem.classes().size());
  for (size_t pass = 0; pass < kMaxHotPasses && !hot_list.empty(); ++pass) {
    if (should_stop()) break;
    for (auto& members : hot_by_colour) members.clear();
    for (uint32_t v : hot_list) hot_by_colour[colour[v]].push_back(v);
    // One colour class at a time, as in a sweep: no two moving vertices share a triangle.
    for (const std::vector<uint32_t>& members : hot_by_colour) {
      const long long count = static_cast<long long>(members.size());
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) if (count >= 256)
      for (long long k = 0; k < count; ++k) {
        const uint32_t v = members[static_cast<size_t>(k)];
        moved[v] = problem.move_vertex(q, v);
      }
    }
    updates += static_cast<double>(hot_list.size());
    // Only the stars of moved vertices changed: the next hot set is among them and their
    // neighbours.
    candidates.clear();
    for (uint32_t v : hot_list) {
      hot[v] = 0;
      if (!(moved[v] > tolerance)) continue;  // stuck where it is: leave it to the sweeps
      if (!seen[v]) seen[v] = 1, candidates.push_back(v);
      problem.for_each_neighbor(v, [&](uint32_t w) {
        if (!seen[w]) seen[w] = 1, candidates.push_back(w);
      });
    }
    hot_list.clear();
    parallel_for(candidates.size(), threads, [&](size_t k) {
      const uint32_t v = candidates[k];
      hot[v] = problem.in_hot_star(q, v, threshold) ? 1 : 0;
    });
    for (uint32_t v : candidates) {
      seen[v] = 0;
      if (hot[v]) hot_list.push_back(v);
    }
  }
  return updates;
}

}  // namespace

StretchStats optimize_stretch(std::span<const Vec3> x, std::span<const Triangle> triangles,
                              std::span<Vec3> q, const StretchOptions& options,
                              const std::function<bool()>& should_stop,
                              std::span<const uint32_t> start, std::span<const double> area_scale) {
  StretchStats stats;
  const size_t n = q.size();
  StretchProblem problem(x, triangles, n, options, area_scale);
  const int threads = resolve_threads(options.threads);
  std::vector<double> moved(n, 0);
  std::vector<char> active(n, start.empty() ? 1 : 0);
  for (uint32_t v : start) active[v] = 1;
  if (start.empty() && options.relieve_hot_spots) {
    problem.rescale(q, threads);
    stats.vertex_updates +=
        relieve_hot_spots(problem, q, threads, options.active_tolerance, should_stop);
  }
  double previous = INFINITY;
  for (; stats.sweeps < options.max_sweeps; ++stats.sweeps) {
    const double energy = problem.rescale(q, threads);
    if (stats.sweeps == 0) stats.initial_energy = energy;
    if (previous - energy < options.relative_decrease * energy) break;
    previous = energy;
    size_t updates = 0;
    for (const std::vector<uint32_t>& members : problem.classes()) {
      if (should_stop()) {
        stats.final_energy = problem.rescale(q, threads);
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
    const size_t still = parallel_count(n, threads, [&](size_t v) {
      bool keep = moved[v] > options.active_tolerance;
      problem.for_each_neighbor(static_cast<uint32_t>(v), [&](uint32_t w) {
        keep = keep || moved[w] > options.active_tolerance;
      });
      active[v] = keep;
      return keep;
    });
    if (still == 0) {
      ++stats.sweeps;
      break;
    }
  }
  if (start.empty() && n <= options.newton_max_vertices) {
    const std::vector<TriangleEnergy> energies = problem.triangle_energies();
    while (stats.newton_steps < options.max_newton_steps && !should_stop()) {
      ++stats.newton_steps;
      const double decrease =
          newton_step(problem.triangles(), energies, problem.surface_total(), q, threads);
      if (!(decrease > 10 * options.relative_decrease)) break;
    }
  }
  stats.final_energy = problem.rescale(q, threads);
  return stats;
}

std::vector<uint32_t> uncertain_vertices(std::span<const Vec3> q,
                                         std::span<const Triangle> triangles) {
  std::vector<char> marked(q.size(), 0);
  for (const Triangle& t : triangles) {
    const Vec3 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
    if (spherical_area(a, b, c) < 100 * kDegenerateArea ||
        !is_valid_triangle(rounded_to_float32(a), rounded_to_float32(b), rounded_to_float32(c)))
      for (uint32_t v : t) marked[v] = 1;
  }
  std::vector<uint32_t> out;
  for (uint32_t v = 0; v < q.size(); ++v)
    if (marked[v]) out.push_back(v);
  return out;
}

}  // namespace spheremap
