#include "core/map/repair.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

constexpr size_t kChunk = 50;
constexpr int kMaxRings = 30;

// Vertices of invalid triangles grown by `rings` rings, and the triangles touching them;
// both ascending (scans in index order), so runs are deterministic.
void active_region(const LaiChengSmoother& s, std::span<const Vec3> q, int rings,
                   std::vector<uint32_t>& vertices, std::vector<uint32_t>& triangles) {
  const auto tris = s.triangles();
  const auto& vt = s.vertex_triangles();
  std::vector<char> in_region(s.vertex_count(), 0);
  std::vector<uint32_t> frontier;
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (!s.triangle_valid(q, t))
      for (uint32_t v : tris[t])
        if (!in_region[v]) in_region[v] = 1, frontier.push_back(v);
  for (int r = 0; r < rings && !frontier.empty(); ++r) {
    std::vector<uint32_t> next;
    for (uint32_t v : frontier)
      for (uint32_t t : vt.of(v))
        for (uint32_t w : tris[t])
          if (!in_region[w]) in_region[w] = 1, next.push_back(w);
    frontier.swap(next);
  }
  vertices.clear();
  std::vector<char> tri_in(tris.size(), 0);
  for (uint32_t v = 0; v < s.vertex_count(); ++v) {
    if (!in_region[v]) continue;
    vertices.push_back(v);
    for (uint32_t t : vt.of(v)) tri_in[t] = 1;
  }
  triangles.clear();
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (tri_in[t]) triangles.push_back(t);
}

}  // namespace

RepairStats local_repair(LaiChengSmoother& smoother, std::span<Vec3> q, size_t folds,
                         size_t max_iterations, const std::function<bool()>& should_stop) {
  RepairStats stats;
  stats.folds = folds;
  int rings = 2;
  std::vector<uint32_t> active, active_triangles;
  smoother.sync_fixed(q);
  while (stats.folds > 0 && stats.iterations < max_iterations && !should_stop()) {
    active_region(smoother, q, rings, active, active_triangles);
    // Asked every iteration too: a chunk on a large region took over a second.
    for (size_t k = 0; k < kChunk && stats.iterations < max_iterations && !should_stop(); ++k) {
      const size_t active_folds = smoother.step_active(q, active, active_triangles);
      ++stats.iterations;
      stats.vertex_updates += static_cast<double>(active.size());
      if (active_folds == 0) break;
    }
    const size_t now = smoother.count_folds(q);
    if (now >= stats.folds) rings = std::min(rings + 1, kMaxRings);
    stats.folds = now;
  }
  return stats;
}

size_t fold_safe_steps(LaiChengSmoother& smoother, std::span<Vec3> q, size_t steps,
                       const std::function<bool()>& should_stop) {
  constexpr int kMaxHalvings = 12;
  const auto tris = smoother.triangles();
  const auto& vt = smoother.vertex_triangles();
  const size_t n = smoother.vertex_count();
  std::vector<char> was_valid(tris.size()), marked(n, 0);
  std::vector<uint8_t> halvings(n);
  std::vector<Vec3> previous(n), target(n);
  std::vector<uint32_t> moved, candidates;
  auto valid = [&](uint32_t t) { return smoother.triangle_valid(q, t); };
  size_t folds = 0;
  for (size_t step = 0; step < steps && !(should_stop && should_stop()); ++step) {
    for (uint32_t t = 0; t < tris.size(); ++t) was_valid[t] = valid(t);
    std::copy(q.begin(), q.end(), previous.begin());
    smoother.step(q);
    std::copy(q.begin(), q.end(), target.begin());
    std::fill(halvings.begin(), halvings.end(), 0);
    // Rounds: mark moved corners of newly invalid triangles, shorten all marked moves at
    // once (order-independent: deterministic). A corner back at its old position is never
    // marked, and a triangle valid with all corners there is valid again: rounds end.
    auto mark = [&](uint32_t t) {
      if (!was_valid[t] || valid(t)) return;
      for (uint32_t v : tris[t])
        if (!(q[v] == previous[v]) && !marked[v]) marked[v] = 1, moved.push_back(v);
    };
    moved.clear();
    for (uint32_t t = 0; t < tris.size(); ++t) mark(t);
    while (!moved.empty()) {
      for (uint32_t v : moved) {
        marked[v] = 0;
        const int h = ++halvings[v];
        const Vec3 partial = previous[v] + std::ldexp(1.0, -h) * (target[v] - previous[v]);
        q[v] = h > kMaxHalvings ? previous[v] : normalized_or(partial, previous[v]);
      }
      candidates.clear();
      for (uint32_t v : moved)
        for (uint32_t t : vt.of(v)) candidates.push_back(t);
      moved.clear();
      for (uint32_t t : candidates) mark(t);
    }
  }
  for (uint32_t t = 0; t < tris.size(); ++t) folds += !valid(t);
  return folds;
}

}  // namespace spheremap
