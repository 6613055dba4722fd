#include "core/map/limit_operator.h"

#include <algorithm>

namespace spheremap {

SparseMatrix limit_operator(std::span<const uint32_t> face_offsets,
                            std::span<const uint32_t> face_indices, size_t vertex_count,
                            double alpha) {
  const size_t face_count = face_offsets.size() - 1;
  // Unmerged entries per row: every corner of every incident face (4/d each, the
  // vertex itself included), one per outgoing half-edge (2 - alpha), one diagonal term.
  std::vector<uint32_t> valence(vertex_count, 0);
  std::vector<uint32_t> start(vertex_count + 1, 0);
  for (size_t f = 0; f < face_count; ++f) {
    const uint32_t d = face_offsets[f + 1] - face_offsets[f];
    for (uint32_t k = face_offsets[f]; k < face_offsets[f + 1]; ++k) {
      ++valence[face_indices[k]];
      start[face_indices[k] + 1] += d + 1;
    }
  }
  for (size_t i = 0; i < vertex_count; ++i) start[i + 1] += start[i] + 1;

  struct Entry {
    uint32_t column;
    double weight;
  };
  std::vector<Entry> entries(start.back());
  std::vector<uint32_t> cursor(start.begin(), start.end() - 1);
  for (uint32_t i = 0; i < vertex_count; ++i) {
    const double n = valence[i];
    entries[cursor[i]++] = {i, (n - 1) * n + n * alpha};
  }
  for (size_t f = 0; f < face_count; ++f) {
    const uint32_t begin = face_offsets[f], d = face_offsets[f + 1] - begin;
    const double share = 4.0 / d;
    for (uint32_t a = 0; a < d; ++a) {
      const uint32_t i = face_indices[begin + a];
      for (uint32_t b = 0; b < d; ++b) entries[cursor[i]++] = {face_indices[begin + b], share};
      // Half-edge i -> next; the opposite face contributes the reverse half-edge.
      entries[cursor[i]++] = {face_indices[begin + (a + 1) % d], 2.0 - alpha};
    }
  }

  SparseMatrix A;
  A.offsets.reserve(vertex_count + 1);
  for (uint32_t i = 0; i < vertex_count; ++i) {
    auto row_begin = entries.begin() + start[i], row_end = entries.begin() + start[i + 1];
    std::sort(row_begin, row_end,
              [](const Entry& x, const Entry& y) { return x.column < y.column; });
    const double n = valence[i], scale = n > 0 ? 1.0 / (n * (n + 5)) : 0.0;
    for (auto it = row_begin; it != row_end;) {
      double b = 0;
      const uint32_t column = it->column;
      for (; it != row_end && it->column == column; ++it) b += it->weight;
      A.columns.push_back(column);
      A.values.push_back(b * scale);
    }
    A.offsets.push_back(static_cast<uint32_t>(A.columns.size()));
  }
  return A;
}

}  // namespace spheremap
