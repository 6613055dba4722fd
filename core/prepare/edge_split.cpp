#include "core/prepare/edge_split.h"

#include <algorithm>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/mesh/union_find.h"
#include "core/prepare/edge_pairing.h"  // sorted_edge_corners, manifold_sheets

namespace spheremap {
namespace {

// Past this many passes over the non-manifold edges (each pass that joins sheets settles
// at least one edge) the rest are joined at once: the loop stays bounded on soups.
constexpr int kMaxPasses = 64;

}  // namespace

EdgeSplit split_non_manifold_edges(PolygonMesh& mesh, const StopCheck* stop) {
  EdgeSplit result;
  const uint32_t faces = static_cast<uint32_t>(mesh.face_count());
  const std::vector<EdgeCorner> corners = sorted_edge_corners(mesh, stop);
  // The non-manifold edges' ranges in `corners`, kept for the passes below.
  UnionFind sheets = manifold_sheets(corners, faces);
  std::vector<std::pair<size_t, size_t>> non_manifold;
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    if (j - i > 2) non_manifold.push_back({i, j});
  }
  if (non_manifold.empty()) return result;
  // A non-manifold edge splits only when each sheet there has exactly two of its faces;
  // otherwise its faces are joined, which may unsettle another edge: repeat until none.
  std::vector<uint32_t> roots;
  auto splits = [&](const std::pair<size_t, size_t>& range) {
    roots.clear();
    for (size_t i = range.first; i < range.second; ++i)
      roots.push_back(sheets.find(corners[i].face));
    std::sort(roots.begin(), roots.end());
    for (size_t i = 0, j = 0; i < roots.size(); i = j) {
      while (j < roots.size() && roots[j] == roots[i]) ++j;
      if (j - i != 2) return false;
    }
    return true;
  };
  auto join = [&](const std::pair<size_t, size_t>& range) {
    bool joined = false;
    for (size_t i = range.first + 1; i < range.second; ++i)
      if (sheets.find(corners[i].face) != sheets.find(corners[range.first].face)) {
        sheets.unite(corners[i].face, corners[range.first].face);
        joined = true;
      }
    return joined;
  };
  for (int pass = 0;; ++pass) {
    if (stop) stop->check();
    bool joined = false;
    for (const auto& range : non_manifold)
      if (pass >= kMaxPasses || !splits(range)) joined |= join(range);
    if (!joined) break;
  }
  for (const auto& range : non_manifold) {
    roots.clear();
    for (size_t i = range.first; i < range.second; ++i)
      roots.push_back(sheets.find(corners[i].face));
    if (std::any_of(roots.begin(), roots.end(), [&](uint32_t r) { return r != roots[0]; }))
      ++result.edges_split;
  }
  if (result.edges_split == 0) return result;
  // Per vertex, its first corner's sheet keeps it; every other sheet gets one copy.
  const uint32_t n = static_cast<uint32_t>(mesh.vertex_count());
  std::vector<uint32_t> keeper(n, UINT32_MAX);
  std::unordered_map<uint64_t, uint32_t> copy_of;  // (vertex << 32 | sheet) -> copy
  for (uint32_t f = 0; f < faces; ++f) {
    if (stop && f % StopCheck::kInterval == 0) stop->check();
    const uint32_t sheet = sheets.find(f);
    for (uint32_t s = mesh.offsets[f]; s < mesh.offsets[f + 1]; ++s) {
      const uint32_t v = mesh.indices[s];
      if (v >= n) continue;
      if (keeper[v] == UINT32_MAX) keeper[v] = sheet;
      if (keeper[v] == sheet) continue;
      const auto [it, added] = copy_of.emplace((uint64_t{v} << 32) | sheet,
                                               static_cast<uint32_t>(mesh.positions.size()));
      if (added) {
        const Vec3 position = mesh.positions[v];
        mesh.positions.push_back(position);
        ++result.vertices_added;
      }
      mesh.indices[s] = it->second;
    }
  }
  return result;
}

}  // namespace spheremap
