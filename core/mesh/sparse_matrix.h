// Compressed sparse row matrix, columns ascending within each row.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/vec3.h"

namespace spheremap {

struct SparseMatrix {
  std::vector<uint32_t> offsets{0};  // rows + 1
  std::vector<uint32_t> columns;
  std::vector<double> values;

  size_t rows() const { return offsets.size() - 1; }
  size_t nonzeros() const { return columns.size(); }
  // Row i applied to x: sum_j A_ij x_j.
  Vec3 row_times(size_t i, std::span<const Vec3> x) const {
    Vec3 sum;
    for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) sum += values[k] * x[columns[k]];
    return sum;
  }
};

}  // namespace spheremap
