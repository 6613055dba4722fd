#include "core/prepare/vertex_split.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "core/mesh/union_find.h"
#include "core/prepare/hole_filling.h"  // undirected_edge_key

namespace spheremap {

VertexSplit split_non_manifold_vertices(PolygonMesh& mesh, const StopCheck* stop,
                                        const EdgePairs* pairs) {
  VertexSplit result;
  const size_t n = mesh.vertex_count();
  // The corners (slots in mesh.indices) of each vertex, in face order.
  std::vector<uint32_t> first(n + 1, 0);
  for (uint32_t v : mesh.indices)
    if (v < n) ++first[v + 1];
  for (size_t v = 0; v < n; ++v) first[v + 1] += first[v];
  std::vector<uint32_t> slots(first.back()), fill(first.begin(), first.end() - 1);
  std::vector<uint32_t> face_of(mesh.indices.size());
  for (uint32_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t s = mesh.offsets[f]; s < mesh.offsets[f + 1]; ++s) {
      face_of[s] = f;
      if (mesh.indices[s] < n) slots[fill[mesh.indices[s]]++] = s;
    }
  auto neighbour = [&](uint32_t slot, int step) {
    const uint32_t f = face_of[slot];
    const uint32_t size = mesh.offsets[f + 1] - mesh.offsets[f];
    const uint32_t k = slot - mesh.offsets[f];
    return mesh.indices[mesh.offsets[f] + (k + size + static_cast<uint32_t>(step)) % size];
  };
  std::vector<std::pair<uint32_t, uint32_t>> by_neighbour;  // (neighbour, local corner)
  for (uint32_t v = 0; v < n; ++v) {
    if (stop && v % StopCheck::kInterval == 0) stop->check();
    const uint32_t degree = first[v + 1] - first[v];
    if (degree < 2) continue;
    by_neighbour.clear();
    for (uint32_t c = 0; c < degree; ++c) {
      by_neighbour.push_back({neighbour(slots[first[v] + c], -1), c});
      by_neighbour.push_back({neighbour(slots[first[v] + c], +1), c});
    }
    std::sort(by_neighbour.begin(), by_neighbour.end());
    UnionFind fans(degree);
    size_t joined = 0;
    auto join = [&](uint32_t x, uint32_t y) {
      const uint32_t a = fans.find(x), b = fans.find(y);
      if (a != b) fans.unite(a, b), ++joined;
    };
    for (size_t k = 0, end = 0; k < by_neighbour.size(); k = end) {
      // The corners beside the edge v -> w: joined in a row, or, at a paired edge, each
      // with its partner's.
      const uint32_t w = by_neighbour[k].first;
      while (end < by_neighbour.size() && by_neighbour[end].first == w) ++end;
      const auto paired =
          pairs ? pairs->find(undirected_edge_key(v, w)) : EdgePairs::const_iterator{};
      if (!pairs || paired == pairs->end()) {
        for (size_t m = k + 1; m < end; ++m)
          join(by_neighbour[m].second, by_neighbour[m - 1].second);
        continue;
      }
      for (size_t m = k; m < end; ++m) {
        const uint32_t face = face_of[slots[first[v] + by_neighbour[m].second]];
        const uint32_t partner = paired_face(*pairs, paired->first, face);
        for (size_t o = k; o < end; ++o)
          if (face_of[slots[first[v] + by_neighbour[o].second]] == partner)
            join(by_neighbour[m].second, by_neighbour[o].second);
      }
    }
    if (joined + 1 == degree) continue;  // one fan
    ++result.vertices_split;
    // The first corner's fan keeps v; each other fan gets a copy.
    std::vector<std::pair<uint32_t, uint32_t>> copy_of_fan;  // (fan root, vertex)
    copy_of_fan.push_back({fans.find(0), v});
    for (uint32_t c = 0; c < degree; ++c) {
      const uint32_t root = fans.find(c);
      auto it = std::find_if(copy_of_fan.begin(), copy_of_fan.end(),
                             [&](const auto& entry) { return entry.first == root; });
      if (it == copy_of_fan.end()) {
        copy_of_fan.push_back({root, static_cast<uint32_t>(mesh.positions.size())});
        const Vec3 position = mesh.positions[v];
        mesh.positions.push_back(position);
        ++result.vertices_added;
        it = copy_of_fan.end() - 1;
      }
      mesh.indices[slots[first[v] + c]] = it->second;
    }
  }
  return result;
}

}  // namespace spheremap
