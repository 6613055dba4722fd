// The generalized Catmull-Clark limit-point operator A (ALGORITHM §A1).
//
// Row i is a convex combination of the vertices sharing a face with i:
//   A_ii = ((n-1)n + n alpha + sum_f 4/d_f) / (n(n+5))
//   A_ij = (2 - alpha + 4/d_1 + 4/d_2) / (n(n+5))   j an edge neighbour (faces d_1, d_2)
//   A_ij = (sum of 4/d_f over faces sharing i, j diagonally) / (n(n+5))
// with n the valence of i and d_f the number of corners of face f.
//
// Precondition: the faces form a closed, consistently oriented manifold over vertices
// [0, vertex_count) (each undirected edge is two opposite half-edges). Depends only on
// connectivity: build once per mesh, alpha in [0, 1] (0 = standard Catmull-Clark).
#pragma once

#include <span>

#include "core/mesh/mesh.h"
#include "core/mesh/sparse_matrix.h"

namespace spheremap {

SparseMatrix limit_operator(std::span<const uint32_t> face_offsets,
                            std::span<const uint32_t> face_indices, size_t vertex_count,
                            double alpha);

inline SparseMatrix limit_operator(const PolygonMesh& mesh, double alpha) {
  return limit_operator(mesh.offsets, mesh.indices, mesh.vertex_count(), alpha);
}

}  // namespace spheremap
