#include "core/map/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/mesh/parallel.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

struct Weighted {
  double value, weight;
};

DistortionSummary summarize(std::vector<Weighted>& samples) {
  DistortionSummary s;
  if (samples.empty()) return s;
  double total = 0, sum = 0;
  for (const Weighted& w : samples) total += w.weight, sum += w.weight * w.value;
  std::sort(samples.begin(), samples.end(),
            [](const Weighted& a, const Weighted& b) { return a.value < b.value; });
  s.mean = total > 0 ? sum / total : 0;
  s.max = samples.back().value;
  double cumulative = 0;
  s.p99 = s.max;
  for (const Weighted& w : samples) {
    cumulative += w.weight;
    if (cumulative >= 0.99 * total) {
      s.p99 = w.value;
      break;
    }
  }
  return s;
}

// Edge vectors of a triangle in an orthonormal frame of its own plane: columns (e1, e2).
struct Frame2 {
  double e1x, e2x, e2y;  // e1 = (e1x, 0), e2 = (e2x, e2y)
};
Frame2 planar(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const double l1 = norm(e1);
  const double x2 = l1 > 0 ? dot(e2, e1) / l1 : 0;
  const double y2 = l1 > 0 ? norm(cross(e1, e2)) / l1 : 0;
  return {l1, x2, y2};
}

// Singular values s1 >= s2 of the 2x2 map taking triangle `from` to triangle `to`.
std::array<double, 2> singular_values(const Frame2& from, const Frame2& to) {
  // J = T F^-1 with F = [[f1, f2x], [0, f2y]], T likewise.
  const double inv_det = 1.0 / (from.e1x * from.e2y);
  const double a = to.e1x / from.e1x;
  const double b = (to.e2x * from.e1x - to.e1x * from.e2x) * inv_det;
  const double d = to.e2y / from.e2y;
  const double frob = a * a + b * b + d * d, det = a * d;
  const double root = std::sqrt(std::max(0.0, frob * frob - 4 * det * det));
  return {std::sqrt((frob + root) / 2), std::sqrt(std::max(0.0, (frob - root) / 2))};
}

double corner_angle(const Vec3& at, const Vec3& p, const Vec3& q) {
  return std::atan2(norm(cross(p - at, q - at)), dot(p - at, q - at));
}

// What one triangle gives the metrics. Computed in parallel a block of triangles at a time
// (the memory stays bounded) and summed in triangle order: the same sums in the same order
// as one serial pass, so the same bits for any thread count.
struct TriangleSample {
  bool measured = false;
  double surface_area, area_log_ratio, dilatation, g1, stretch, angle_error;
};

constexpr size_t kBlock = size_t{1} << 16;

double surface_area_of(std::span<const Vec3> x, const Triangle& t) {
  return 0.5 * norm(cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]));
}

}  // namespace

QualityMetrics compute_metrics(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                               std::span<const Triangle> triangles, int threads,
                               double sphere_share) {
  threads = resolve_threads(threads);
  QualityMetrics m;
  const size_t count = triangles.size();
  double surface_total = 0, chord_total = 0;
  {
    std::vector<std::array<double, 2>> areas(std::min(count, kBlock));
    for (size_t begin = 0; begin < count; begin += kBlock) {
      const size_t size = std::min(kBlock, count - begin);
      parallel_for(size, threads, [&](size_t k) {
        const Triangle& t = triangles[begin + k];
        areas[k] = {surface_area_of(surface, t), surface_area_of(sphere, t)};
      });
      for (size_t k = 0; k < size; ++k) surface_total += areas[k][0], chord_total += areas[k][1];
    }
  }
  const double chord_scale = chord_total > 0 ? std::sqrt(surface_total / chord_total) : 0;
  std::vector<Weighted> area_samples, dilatation_samples;
  double stretch_sum = 0, stretch_weight = 0, angle_error_sum = 0;
  std::vector<TriangleSample> samples(std::min(count, kBlock));
  for (size_t begin = 0; begin < count; begin += kBlock) {
    const size_t size = std::min(kBlock, count - begin);
    parallel_for(size, threads, [&](size_t k) {
      const Triangle& t = triangles[begin + k];
      const Vec3 &a = surface[t[0]], &b = surface[t[1]], &c = surface[t[2]];
      const Vec3 &p = sphere[t[0]], &q = sphere[t[1]], &r = sphere[t[2]];
      const double surface_area = surface_area_of(surface, t);
      const double sphere_area = spherical_area(p, q, r);
      const Frame2 from = planar(a, b, c), to = planar(p, q, r);
      TriangleSample& sample = samples[k];
      sample.measured = surface_area > 0 && sphere_area > 0 && from.e1x > 0 && from.e2y > 0 &&
                        to.e1x > 0 && to.e2y > 0;
      if (!sample.measured) return;
      sample.surface_area = surface_area;
      const double ratio = (sphere_area / sphere_share) / (surface_area / surface_total);
      sample.area_log_ratio = std::abs(std::log(ratio));
      const auto [s1, s2] = singular_values(from, to);
      sample.dilatation = s1 / s2;
      // Stretch of the inverse map (chord triangle scaled to surface area -> surface).
      const double g1 = 1.0 / (chord_scale * s2), g2 = 1.0 / (chord_scale * s1);
      sample.g1 = g1;
      sample.stretch = surface_area * (g1 * g1 + g2 * g2) / 2;
      sample.angle_error = std::abs(corner_angle(a, b, c) - corner_angle(p, q, r)) +
                           std::abs(corner_angle(b, c, a) - corner_angle(q, r, p)) +
                           std::abs(corner_angle(c, a, b) - corner_angle(r, p, q));
    });
    for (size_t k = 0; k < size; ++k) {
      const TriangleSample& sample = samples[k];
      if (!sample.measured) {
        ++m.skipped_triangles;
        continue;
      }
      ++m.measured_triangles;
      area_samples.push_back({sample.area_log_ratio, sample.surface_area});
      dilatation_samples.push_back({sample.dilatation, sample.surface_area});
      stretch_sum += sample.stretch;
      stretch_weight += sample.surface_area;
      m.stretch_linf = std::max(m.stretch_linf, sample.g1);
      angle_error_sum += sample.angle_error;
    }
  }
  // Two independent sorts: side by side when there are threads for them.
#pragma omp parallel sections num_threads(std::min(threads, 2)) if (count >= kParallelThreshold)
  {
#pragma omp section
    m.area_log_ratio = summarize(area_samples);
#pragma omp section
    m.dilatation = summarize(dilatation_samples);
  }
  m.stretch_l2 = stretch_weight > 0 ? std::sqrt(stretch_sum / stretch_weight) : 0;
  m.angle_error_degrees =
      m.measured_triangles ? angle_error_sum * 180 / M_PI / (3.0 * m.measured_triangles) : 0;
  return m;
}

}  // namespace spheremap
