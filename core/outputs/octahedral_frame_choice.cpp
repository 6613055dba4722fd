#include "core/outputs/octahedral_frame_choice.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

#include "core/mesh/stop_check.h"
#include "core/mesh/surface_distance.h"
#include "core/outputs/remesh.h"

namespace spheremap {
namespace {

double l1_norm(const Vec3& d) {
  return std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
}

// The radical inverse of k in `base`: the Halton sequence's k-th coordinate, in [0, 1).
double radical_inverse(int k, int base) {
  double inverse = 0, digit_weight = 1.0 / base;
  for (; k > 0; k /= base, digit_weight /= base) inverse += (k % base) * digit_weight;
  return inverse;
}

// The largest, over vertices, of (A_v / S_v) |R^T q_v|_1^3 (the spacing squared).
double largest_spacing_squared(std::span<const Vec3> sphere,
                               const std::vector<double>& area_per_chord,
                               const OctahedralFrame& frame) {
  double largest = 0;
  for (size_t v = 0; v < sphere.size(); ++v) {
    if (area_per_chord[v] <= 0) continue;
    const double l1 = l1_norm(frame.from_sphere(sphere[v]));
    largest = std::max(largest, area_per_chord[v] * l1 * l1 * l1);
  }
  return largest;
}

// The centroids of the remesh's triangles, where sampled errors are measured.
std::vector<Vec3> remesh_centroids(const OctahedralRemesh& remesh) {
  std::vector<Vec3> centroids;
  centroids.reserve(remesh.triangles.size());
  for (const Triangle& t : remesh.triangles)
    centroids.push_back((remesh.positions[t[0]] + remesh.positions[t[1]] + remesh.positions[t[2]]) *
                        (1.0 / 3));
  return centroids;
}

}  // namespace

OctahedralFrame frame_candidate(int k) {
  // Shoemake's uniform rotation from three numbers in [0, 1) (offset by one so the first
  // candidate is not the Halton origin).
  const double u1 = radical_inverse(k + 1, 2), u2 = radical_inverse(k + 1, 3),
               u3 = radical_inverse(k + 1, 5);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const double t2 = 2 * std::numbers::pi * u2, t3 = 2 * std::numbers::pi * u3;
  const double w = b * std::cos(t3), x = a * std::sin(t2), y = a * std::cos(t2),
               z = b * std::sin(t3);
  OctahedralFrame f;
  auto& r = f.rotation;
  r[0][0] = 1 - 2 * (y * y + z * z), r[0][1] = 2 * (x * y - z * w), r[0][2] = 2 * (x * z + y * w);
  r[1][0] = 2 * (x * y + z * w), r[1][1] = 1 - 2 * (x * x + z * z), r[1][2] = 2 * (y * z - x * w);
  r[2][0] = 2 * (x * z - y * w), r[2][1] = 2 * (y * z + x * w), r[2][2] = 1 - 2 * (x * x + y * y);
  return f;
}

size_t frames_tried(size_t most, int resolution) {
  const double share = static_cast<double>(kFrameSearchResolution) / std::max(resolution, 1);
  const auto scaled = static_cast<size_t>(static_cast<double>(most) * share * share);
  return std::clamp<size_t>(scaled, 1, most);
}

namespace {

// The choice by `largest` (a candidate frame's largest predicted figure): every
// candidate ranked, ties in candidate order.
template <typename Largest>
FrameChoice ranked_choice(const Largest& largest) {
  FrameChoice choice;
  choice.unturned_largest = largest(OctahedralFrame{});
  std::vector<double> figure(kFrameCandidates);
  for (int k = 0; k < kFrameCandidates; ++k) {
    const double value = largest(frame_candidate(k));
    figure[k] = std::isnan(value) ? INFINITY : value;
  }
  choice.ranked.resize(kFrameCandidates);
  std::iota(choice.ranked.begin(), choice.ranked.end(), 0);
  std::stable_sort(choice.ranked.begin(), choice.ranked.end(),
                   [&](int a, int b) { return figure[a] < figure[b]; });
  choice.frame = frame_candidate(choice.ranked.front());
  choice.predicted_largest = figure[choice.ranked.front()];
  return choice;
}

}  // namespace

FrameChoice choose_octahedral_frame(std::span<const Vec3> surface, std::span<const Vec3> sphere,
                                    std::span<const Triangle> triangles) {
  // Per vertex, the surface area and the chord area of its triangles (the ring smooths a
  // single sliver's ratio, which says little about the sampling around it).
  std::vector<double> area(sphere.size(), 0), chord(sphere.size(), 0);
  double total_area = 0, total_chord = 0;
  for (const Triangle& t : triangles) {
    const double a =
        0.5 * norm(cross(surface[t[1]] - surface[t[0]], surface[t[2]] - surface[t[0]]));
    const double c = 0.5 * norm(cross(sphere[t[1]] - sphere[t[0]], sphere[t[2]] - sphere[t[0]]));
    if (!(c > 0) || !std::isfinite(a)) continue;
    total_area += a, total_chord += c;
    for (uint32_t v : t) area[v] += a, chord[v] += c;
  }
  std::vector<double> area_per_chord(sphere.size(), 0);
  if (total_area > 0 && total_chord > 0)
    for (size_t v = 0; v < sphere.size(); ++v)
      if (chord[v] > 0) area_per_chord[v] = (area[v] / total_area) / (chord[v] / total_chord);
  return ranked_choice([&](const OctahedralFrame& frame) {
    return std::sqrt(largest_spacing_squared(sphere, area_per_chord, frame));
  });
}

std::vector<SampledError> sampled_errors(const SurfaceMeasure& measured_surface,
                                         std::span<const Vec3> surface,
                                         std::span<const Vec3> sphere,
                                         const OctahedralRemesh& remesh, int threads,
                                         const std::function<bool()>* should_stop) {
  std::vector<SampledError> errors;
  // The remesh's triangles, at their centroids (a triangle bridging a gap is off the
  // surface there), each at the sphere point of its centroid in the square.
  const std::vector<Vec3> centroids = remesh_centroids(remesh);
  const PointDistances off = measured_surface.point_distances(centroids, threads, should_stop);
  for (size_t k = 0; k < remesh.triangles.size(); ++k) {
    const Triangle& t = remesh.triangles[k];
    const Vec2 centre{
        (remesh.square[t[0]][0] + remesh.square[t[1]][0] + remesh.square[t[2]][0]) / 3,
        (remesh.square[t[0]][1] + remesh.square[t[1]][1] + remesh.square[t[2]][1]) / 3};
    errors.push_back({octahedral_decode(centre, remesh.frame), off.relative[k]});
  }
  // The surface's vertices, at their sphere points (a feature the samples missed).
  const PointDistances missed =
      point_distances(remesh.positions, remesh.triangles, surface, threads, should_stop);
  for (size_t v = 0; v < surface.size(); ++v) errors.push_back({sphere[v], missed.relative[v]});
  return errors;
}

double largest_sampled_error(const SurfaceMeasure& measured_surface, std::span<const Vec3> surface,
                             const OctahedralRemesh& remesh, int threads,
                             const std::function<bool()>* should_stop) {
  const double off =
      measured_surface.largest_point_distance(remesh_centroids(remesh), threads, should_stop);
  StopCheck(should_stop).check();
  const double missed = SurfaceMeasure(remesh.positions, remesh.triangles)
                            .largest_point_distance(surface, threads, should_stop);
  return std::max(off, missed);
}

FrameChoice choose_octahedral_frame(std::span<const SampledError> errors,
                                    const OctahedralFrame& measured) {
  // Only errors that some frame could make the largest: a spacing changes by at most
  // sqrt(5.2) either way, so one under 1/5.2 of the largest stays under it.
  double largest = 0;
  for (const SampledError& e : errors) largest = std::max(largest, e.error);
  struct Spot {
    Vec3 direction;
    double error_per_spacing;
  };
  std::vector<Spot> spots;
  for (const SampledError& e : errors)
    if (e.error >= largest / 5.2 && e.error > 0) {
      const double l1 = l1_norm(measured.from_sphere(e.direction));
      spots.push_back({e.direction, e.error / std::pow(l1, 1.5)});
    }
  const auto predicted = [&](const OctahedralFrame& frame) {
    double worst = 0;
    for (const Spot& s : spots)
      worst = std::max(
          worst, s.error_per_spacing * std::pow(l1_norm(frame.from_sphere(s.direction)), 1.5));
    return worst;
  };
  return ranked_choice(predicted);
}

}  // namespace spheremap
