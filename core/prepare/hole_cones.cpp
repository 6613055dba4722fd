#include "core/prepare/hole_cones.h"

#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh/union_find.h"
#include "core/prepare/edge_pairing.h"  // sorted_edge_corners

namespace spheremap {

HoleCones cone_holes_of_parts_with_handles(PolygonMesh& mesh, const StopCheck* stop) {
  HoleCones result;
  result.first_face = mesh.face_count();
  const uint32_t faces = static_cast<uint32_t>(mesh.face_count());
  const uint32_t n = static_cast<uint32_t>(mesh.vertex_count());
  const std::vector<EdgeCorner> corners = sorted_edge_corners(mesh, stop);
  // Parts: faces joined across every edge they share.
  UnionFind parts(faces);
  for (size_t k = 1; k < corners.size(); ++k)
    if (corners[k].edge == corners[k - 1].edge) parts.unite(corners[k - 1].face, corners[k].face);
  // Per part (at its root face): V - E + F and whether it qualifies.
  std::vector<int64_t> euler(faces, 0);
  std::vector<char> unfit(faces, 0);
  std::vector<uint32_t> part_of_vertex(n, UINT32_MAX);
  std::vector<uint32_t> next(n, UINT32_MAX);  // along a boundary loop, the way faces run it
  for (uint32_t f = 0; f < faces; ++f) {
    const uint32_t part = parts.find(f);
    ++euler[part];
    for (uint32_t v : mesh.face(f)) {
      if (v >= n) {
        unfit[part] = 1;
        continue;
      }
      if (part_of_vertex[v] == UINT32_MAX) {
        part_of_vertex[v] = part, ++euler[part];
      } else if (part_of_vertex[v] != part) {  // parts sharing a vertex: no Euler count
        unfit[part] = unfit[part_of_vertex[v]] = 1;
      }
    }
  }
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    const uint32_t part = parts.find(corners[i].face);
    --euler[part];
    if (j - i > 2 || (j - i == 2 && corners[i].forward == corners[i + 1].forward)) {
      unfit[part] = 1;
      continue;
    }
    if (j - i == 2) continue;
    const uint32_t lo = static_cast<uint32_t>(corners[i].edge >> 32);
    const uint32_t hi = static_cast<uint32_t>(corners[i].edge);
    const uint32_t a = corners[i].forward ? lo : hi, b = corners[i].forward ? hi : lo;
    if (next[a] != UINT32_MAX) unfit[part] = 1;  // two boundary edges run out of a
    next[a] = b;
  }
  // Loops: followed from each boundary vertex not yet on one.
  std::vector<std::vector<uint32_t>> loops;
  std::vector<uint32_t> loop_part;
  std::vector<size_t> loops_of(faces, 0);
  std::vector<char> on_loop(n, 0);
  for (uint32_t v = 0; v < n; ++v) {
    if (next[v] == UINT32_MAX || on_loop[v]) continue;
    const uint32_t part = part_of_vertex[v];
    std::vector<uint32_t> loop;
    uint32_t u = v;
    while (u != UINT32_MAX && !on_loop[u] && loop.size() <= n) {
      on_loop[u] = 1;
      loop.push_back(u);
      u = next[u];
    }
    if (u != v) unfit[part] = 1;  // not closed where it started
    ++loops_of[part];
    loops.push_back(std::move(loop));
    loop_part.push_back(part);
  }
  // Genus from chi = 2 - 2g - b: only parts with handles are coned.
  auto coned = [&](uint32_t part) {
    const int64_t twice_genus = 2 - euler[part] - static_cast<int64_t>(loops_of[part]);
    return !unfit[part] && loops_of[part] > 0 && twice_genus >= 2 && twice_genus % 2 == 0;
  };
  std::vector<char> counted(faces, 0);
  for (size_t l = 0; l < loops.size(); ++l) {
    if (stop) stop->check();
    const uint32_t part = loop_part[l];
    if (!coned(part)) continue;
    if (!counted[part]) counted[part] = 1, ++result.parts;
    Vec3 centroid;
    for (uint32_t v : loops[l]) centroid += mesh.positions[v];
    mesh.positions.push_back(centroid * (1.0 / static_cast<double>(loops[l].size())));
    const uint32_t apex = static_cast<uint32_t>(mesh.positions.size() - 1);
    for (size_t k = 0; k < loops[l].size(); ++k) {
      const uint32_t a = loops[l][k], b = loops[l][(k + 1) % loops[l].size()];
      mesh.add_face(std::array{b, a, apex});
      ++result.faces;
    }
    ++result.loops;
  }
  return result;
}

}  // namespace spheremap
