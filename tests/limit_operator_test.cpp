#include <gtest/gtest.h>

#include "core/map/limit_operator.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

double entry(const SparseMatrix& A, uint32_t i, uint32_t j) {
  for (uint32_t k = A.offsets[i]; k < A.offsets[i + 1]; ++k)
    if (A.columns[k] == j) return A.values[k];
  return 0;
}

void expect_rows_sum_to_one_and_positive(const SparseMatrix& A) {
  for (size_t i = 0; i < A.rows(); ++i) {
    double sum = 0;
    for (uint32_t k = A.offsets[i]; k < A.offsets[i + 1]; ++k) {
      EXPECT_GT(A.values[k], 0);
      sum += A.values[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "row " << i;
  }
}

TEST(LimitOperator, RowsSumToOneForEveryAlpha) {
  for (double alpha : {0.0, 0.5, 1.0}) {
    expect_rows_sum_to_one_and_positive(limit_operator(testing::icosphere(2), alpha));
    expect_rows_sum_to_one_and_positive(limit_operator(testing::quad_cube(3), alpha));
    expect_rows_sum_to_one_and_positive(limit_operator(testing::capped_tube(7, 5, 3), alpha));
  }
}

TEST(LimitOperator, RegularQuadVertexIsTheBicubicMask) {
  const PolygonMesh cube = testing::quad_cube(4);
  const SparseMatrix A = limit_operator(cube, 0.0);
  // A vertex at the centre of a cube face: valence 4, four quads.
  uint32_t centre = 0;
  for (uint32_t v = 0; v < cube.vertex_count(); ++v)
    if (cube.positions[v].x == 1.0 && cube.positions[v].y == 0.0 && cube.positions[v].z == 0.0)
      centre = v;
  ASSERT_EQ(A.offsets[centre + 1] - A.offsets[centre], 9u);  // itself, 4 edges, 4 diagonals
  EXPECT_NEAR(entry(A, centre, centre), 16.0 / 36, 1e-15);
  int edge = 0, diagonal = 0;
  for (uint32_t k = A.offsets[centre]; k < A.offsets[centre + 1]; ++k) {
    if (A.columns[k] == centre) continue;
    const double d2 = squared_norm(cube.positions[A.columns[k]] - cube.positions[centre]);
    if (d2 < 0.26) {
      EXPECT_NEAR(A.values[k], 4.0 / 36, 1e-15);
      ++edge;
    } else {
      EXPECT_NEAR(A.values[k], 1.0 / 36, 1e-15);
      ++diagonal;
    }
  }
  EXPECT_EQ(edge, 4);
  EXPECT_EQ(diagonal, 4);
}

TEST(LimitOperator, ValenceSixTriangleRow) {
  const PolygonMesh sphere = testing::icosphere(2);
  const SparseMatrix A = limit_operator(sphere, 0.0);
  int checked = 0;
  for (uint32_t i = 0; i < sphere.vertex_count(); ++i) {
    if (A.offsets[i + 1] - A.offsets[i] != 7) continue;  // valence 6
    EXPECT_NEAR(entry(A, i, i), 38.0 / 66, 1e-15);
    for (uint32_t k = A.offsets[i]; k < A.offsets[i + 1]; ++k)
      if (A.columns[k] != i) {
        EXPECT_NEAR(A.values[k], (14.0 / 3) / 66, 1e-15);
      }
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(LimitOperator, AlphaMovesWeightFromEdgesToCentre) {
  const PolygonMesh sphere = testing::icosphere(1);
  const SparseMatrix a0 = limit_operator(sphere, 0.0), a1 = limit_operator(sphere, 1.0);
  const uint32_t i = 20;  // a valence-6 vertex
  const double n = 6;
  EXPECT_NEAR(entry(a1, i, i) - entry(a0, i, i), n / (n * (n + 5)), 1e-15);
  const uint32_t j = a0.columns[a0.offsets[i] + (a0.columns[a0.offsets[i]] == i ? 1 : 0)];
  EXPECT_NEAR(entry(a0, i, j) - entry(a1, i, j), 1.0 / (n * (n + 5)), 1e-15);
}

TEST(LimitOperator, PentagonsGetDiagonalWeights) {
  const PolygonMesh tube = testing::capped_tube(5, 3, 2);  // two pentagon caps
  const SparseMatrix A = limit_operator(tube, 0.0);
  // Vertex 0 is on the bottom pentagon: vertices 2 and 3 of that cap are its diagonals.
  EXPECT_GT(entry(A, 0, 2), 0);
  EXPECT_GT(entry(A, 0, 3), 0);
  // Valence 3 (two ring edges, one along the tube): b = 4/5 from the pentagon alone.
  EXPECT_NEAR(entry(A, 0, 2), (4.0 / 5) / (3 * 8), 1e-15);
}

}  // namespace
}  // namespace spheremap
