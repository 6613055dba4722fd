#include "core/prepare/connected_parts.h"

#include <algorithm>
#include <numeric>

#include "core/mesh/union_find.h"
#include "core/mesh/weld.h"

namespace spheremap {

std::vector<MeshPart> connected_parts(const PolygonMesh& mesh, const StopCheck* stop) {
  UnionFind sets(mesh.vertex_count());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  if (stop) stop->check();
  // Parts numbered in order of their first face, then sorted by size.
  std::vector<uint32_t> part_of_root(mesh.vertex_count(), kUnreferenced);
  std::vector<size_t> faces_of, first_face_of;
  std::vector<uint32_t> face_part(mesh.face_count());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    uint32_t& part = part_of_root[sets.find(mesh.face(f)[0])];
    if (part == kUnreferenced) {
      part = static_cast<uint32_t>(faces_of.size());
      faces_of.push_back(0);
      first_face_of.push_back(f);
    }
    ++faces_of[part];
    face_part[f] = part;
  }
  std::vector<uint32_t> order(faces_of.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return faces_of[a] > faces_of[b]; });
  std::vector<uint32_t> rank(order.size());
  for (uint32_t r = 0; r < order.size(); ++r) rank[order[r]] = r;

  std::vector<MeshPart> parts(order.size());
  std::vector<uint32_t> local(mesh.vertex_count(), kUnreferenced);
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    MeshPart& part = parts[rank[face_part[f]]];
    corners.clear();
    for (uint32_t v : mesh.face(f)) {
      if (local[v] == kUnreferenced) {
        local[v] = static_cast<uint32_t>(part.vertex.size());
        part.vertex.push_back(v);
        part.mesh.positions.push_back(mesh.positions[v]);
      }
      corners.push_back(local[v]);
    }
    part.mesh.add_face(corners);
  }
  return parts;
}

}  // namespace spheremap
