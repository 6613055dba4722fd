#include "core/map/vertex_coloring.h"

#include <algorithm>

namespace spheremap {

std::vector<std::vector<uint32_t>> color_classes(std::span<const Triangle> triangles, size_t n) {
  // Neighbours through triangles (each edge seen from both of its triangles: duplicates
  // do no harm here).
  std::vector<uint32_t> offsets(n + 1, 0);
  for (const Triangle& t : triangles)
    for (uint32_t v : t) offsets[v + 1] += 2;
  for (size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
  std::vector<uint32_t> neighbors(offsets.back());
  std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      neighbors[fill[t[k]]++] = t[(k + 1) % 3];
      neighbors[fill[t[k]]++] = t[(k + 2) % 3];
    }

  constexpr uint32_t kNone = ~0u;
  std::vector<uint32_t> color(n, kNone);
  std::vector<uint32_t> seen_at;  // seen_at[c] == v: colour c is taken around v
  std::vector<std::vector<uint32_t>> classes;
  for (uint32_t v = 0; v < n; ++v) {
    for (uint32_t i = offsets[v]; i < offsets[v + 1]; ++i) {
      const uint32_t c = color[neighbors[i]];
      if (c != kNone) seen_at[c] = v;
    }
    uint32_t c = 0;
    while (c < seen_at.size() && seen_at[c] == v) ++c;
    if (c == seen_at.size()) {
      seen_at.push_back(kNone);
      classes.emplace_back();
    }
    color[v] = c;
    classes[c].push_back(v);
  }
  return classes;
}

}  // namespace spheremap
