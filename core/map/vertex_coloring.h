// Greedy vertex colouring of a triangle mesh's edge graph, for lock-free parallel
// vertex updates: no two vertices of a class share a triangle, so moving one class at a
// time on all threads touches every star from one thread only.
#pragma once

#include <cstdint>
#include <vector>

namespace spheremap {

// Classes of vertex ids 0..n-1 (ascending within a class), colours in first-use order;
// deterministic. for_each_neighbor(v, visit) calls visit(w) for each vertex w sharing a
// triangle with v (repeats do no harm). Vertices with no neighbour get colour 0. At most
// max valence + 1 classes. The caller's own star lists serve as the neighbour lists: a
// list built here was 24 bytes per triangle, the optimizer's peak at 17M triangles.
template <class ForEachNeighbor>
std::vector<std::vector<uint32_t>> color_classes(size_t n, ForEachNeighbor&& for_each_neighbor) {
  constexpr uint32_t kNone = ~0u;
  std::vector<uint32_t> color(n, kNone);
  std::vector<uint32_t> seen_at;  // seen_at[c] == v: colour c is taken around v
  std::vector<std::vector<uint32_t>> classes;
  for (uint32_t v = 0; v < n; ++v) {
    for_each_neighbor(v, [&](uint32_t w) {
      const uint32_t c = color[w];
      if (c != kNone) seen_at[c] = v;
    });
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
