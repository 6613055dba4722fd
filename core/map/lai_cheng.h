// One step of the Lai-Cheng smoothing on the sphere (ALGORITHM §A3, decisions of §B3),
// on one mesh (one level of the hierarchy, or the whole mesh):
//   X = P(A Q)                                   limit-point smoothing, P = normalize
//   X = P(sum_t |E_t| c_t / sum_t |E_t|)         centroid relaxation over incident triangles
//                                                (c_t = P(mean of corners), |E_t| unsigned
//                                                 spherical area: signed weights diverge)
//   X = P(X + u (X - Q))                         offset, placed after the centroid move by
//                                                default (measured 13-22% fewer iterations, no
//                                                stuck fixed points); `kPaper` puts it between
//                                                the A-step and the centroid move, as the paper.
// Steps are Jacobi (every vertex reads the previous iterate), deterministic for any thread
// count, and allocate nothing: buffers are sized once at construction.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/sparse_matrix.h"

namespace spheremap {

enum class OffsetPlacement { kAfterCentroid, kPaper };

struct SmoothingOptions {
  double offset = 0.25;  // u; 0 disables the offset
  OffsetPlacement placement = OffsetPlacement::kAfterCentroid;
  bool centroid_relaxation = true;
  // A-step weight w: X = P((1 - w) Q + w A Q). 1 is the paper. 0.5 (default) halves the
  // pull of the limit operator, whose harmonic-like fixed point squeezes long limbs
  // exponentially; measured on the corpus: horse's smallest triangle 1e-17 -> 9e-14 and
  // 432 -> 0 degenerate triangles, scorpion mapped, 13 of 14 meshes on a first attempt.
  double limit_weight = 0.5;
  // Gauss-Seidel: vertices updated in order, each reading its neighbours' new positions
  // (serial). Jacobi (false) reads the previous iterate and runs in parallel.
  bool gauss_seidel = false;
  int threads = 0;  // 0 = all cores
};

class LaiChengSmoother {
 public:
  // triangles: oriented so a valid map has positive determinants; operator_A rows =
  // vertices [0, vertex_count) of the positions passed to step().
  LaiChengSmoother(std::span<const Triangle> triangles, SparseMatrix operator_A,
                   size_t vertex_count, SmoothingOptions options);

  // One step on every vertex of q (size vertex_count); returns the folds of the new q.
  size_t step(std::span<Vec3> q);

  // One step moving only `active` vertices; `active_triangles` must hold every triangle
  // touching them. Returns the folds among active_triangles. Call sync_fixed(q) after
  // q changes outside step_active (fixed vertices are read from the work buffer).
  size_t step_active(std::span<Vec3> q, std::span<const uint32_t> active,
                     std::span<const uint32_t> active_triangles);
  void sync_fixed(std::span<const Vec3> q);

  size_t count_folds(std::span<const Vec3> q) const;
  bool triangle_valid(std::span<const Vec3> q, uint32_t t) const;

  std::span<const Triangle> triangles() const { return triangles_; }
  const VertexTriangles& vertex_triangles() const { return vertex_triangles_; }
  const SparseMatrix& operator_A() const { return A_; }
  size_t vertex_count() const { return vertex_count_; }

 private:
  template <class Indices, class TriangleIndices>
  void smooth(std::span<Vec3> q, const Indices& vertices, const TriangleIndices& tris);
  void gauss_seidel_sweep(std::span<Vec3> q) const;

  std::span<const Triangle> triangles_;
  SparseMatrix A_;
  size_t vertex_count_;
  SmoothingOptions options_;
  int threads_;
  VertexTriangles vertex_triangles_;
  std::vector<Vec3> work_;                // X, per vertex
  std::vector<Vec3> weighted_centroids_;  // |E_t| c_t, per triangle
};

}  // namespace spheremap
