#include "core/map/lai_cheng.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/parallel.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// Index sets: all of [0, n) or an explicit list.
struct AllIndices {
  size_t n;
  size_t size() const { return n; }
  uint32_t operator[](size_t k) const { return static_cast<uint32_t>(k); }
};
struct ListIndices {
  std::span<const uint32_t> list;
  size_t size() const { return list.size(); }
  uint32_t operator[](size_t k) const { return list[k]; }
};

}  // namespace

LaiChengSmoother::LaiChengSmoother(std::span<const Triangle> triangles, SparseMatrix operator_A,
                                   size_t vertex_count, SmoothingOptions options)
    : triangles_(triangles),
      A_(std::move(operator_A)),
      vertex_count_(vertex_count),
      options_(options),
      threads_(resolve_threads(options.threads)),
      vertex_triangles_(spheremap::vertex_triangles(triangles, vertex_count)),
      work_(vertex_count),
      weighted_centroids_(triangles.size()) {}

template <class Indices, class TriangleIndices>
void LaiChengSmoother::smooth(std::span<Vec3> q, const Indices& vertices,
                              const TriangleIndices& tris) {
  const double u = options_.offset;
  const bool paper_order = options_.placement == OffsetPlacement::kPaper;
  Vec3* x = work_.data();
  parallel_for(vertices.size(), threads_, [&](size_t k) {
    const uint32_t i = vertices[k];
    const double w = options_.limit_weight;
    Vec3 xi = normalized_or(w == 1.0 ? A_.row_times(i, q) : (1 - w) * q[i] + w * A_.row_times(i, q),
                            q[i]);
    if (paper_order && u != 0) xi = normalized_or(xi + u * (xi - q[i]), xi);
    x[i] = xi;
  });
  if (options_.centroid_relaxation) {
    parallel_for(tris.size(), threads_, [&](size_t k) {
      const uint32_t t = tris[k];
      const Vec3 &a = x[triangles_[t][0]], &b = x[triangles_[t][1]], &c = x[triangles_[t][2]];
      const double area = unsigned_area_weight(a, b, c);
      const Vec3 centroid = normalized_or(a + b + c, Vec3{});
      weighted_centroids_[t] = std::isfinite(area) ? area * centroid : Vec3{};
    });
  }
  parallel_for(vertices.size(), threads_, [&](size_t k) {
    const uint32_t i = vertices[k];
    Vec3 xi = x[i];
    if (options_.centroid_relaxation) {
      Vec3 sum;
      for (uint32_t t : vertex_triangles_.of(i)) sum += weighted_centroids_[t];
      xi = normalized_or(sum, xi);
    }
    if (!paper_order && u != 0) xi = normalized_or(xi + u * (xi - q[i]), xi);
    q[i] = xi;
  });
}

size_t LaiChengSmoother::step(std::span<Vec3> q) {
  if (options_.gauss_seidel)
    gauss_seidel_sweep(q);
  else
    smooth(q, AllIndices{vertex_count_}, AllIndices{triangles_.size()});
  return count_folds(q);
}

void LaiChengSmoother::gauss_seidel_sweep(std::span<Vec3> q) const {
  const double u = options_.offset;
  const bool paper_order = options_.placement == OffsetPlacement::kPaper;
  for (uint32_t i = 0; i < vertex_count_; ++i) {
    const Vec3 previous = q[i];
    Vec3 xi = normalized_or(A_.row_times(i, q), previous);
    if (paper_order && u != 0) xi = normalized_or(xi + u * (xi - previous), xi);
    if (options_.centroid_relaxation) {
      Vec3 sum;
      q[i] = xi;
      for (uint32_t t : vertex_triangles_.of(i)) {
        const Vec3 &a = q[triangles_[t][0]], &b = q[triangles_[t][1]], &c = q[triangles_[t][2]];
        const double area = std::abs(spherical_area(a, b, c));
        if (std::isfinite(area)) sum += area * normalized_or(a + b + c, Vec3{});
      }
      xi = normalized_or(sum, xi);
    }
    if (!paper_order && u != 0) xi = normalized_or(xi + u * (xi - previous), xi);
    q[i] = xi;
  }
}

size_t LaiChengSmoother::step_active(std::span<Vec3> q, std::span<const uint32_t> active,
                                     std::span<const uint32_t> active_triangles) {
  smooth(q, ListIndices{active}, ListIndices{active_triangles});
  // Fixed vertices must read as their position in the next triangle pass.
  for (uint32_t i : active) work_[i] = q[i];
  return parallel_count(active_triangles.size(), threads_,
                        [&](size_t k) { return !triangle_valid(q, active_triangles[k]); });
}

void LaiChengSmoother::sync_fixed(std::span<const Vec3> q) {
  std::copy(q.begin(), q.begin() + static_cast<long>(vertex_count_), work_.begin());
}

bool LaiChengSmoother::triangle_valid(std::span<const Vec3> q, uint32_t t) const {
  const Triangle& tri = triangles_[t];
  return is_valid_triangle(q[tri[0]], q[tri[1]], q[tri[2]]);
}

size_t LaiChengSmoother::count_folds(std::span<const Vec3> q) const {
  return parallel_count(triangles_.size(), threads_,
                        [&](size_t t) { return !triangle_valid(q, static_cast<uint32_t>(t)); });
}

}  // namespace spheremap
