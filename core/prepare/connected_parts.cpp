#include "core/prepare/connected_parts.h"

#include <algorithm>
#include <numeric>

#include "core/mesh/submesh.h"
#include "core/mesh/union_find.h"
#include "core/mesh/weld.h"

namespace spheremap {

std::vector<std::vector<uint32_t>> connected_part_faces(const PolygonMesh& mesh,
                                                        const StopCheck* stop) {
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

  // Each part's faces in the whole's order.
  std::vector<std::vector<uint32_t>> part_faces(order.size());
  for (uint32_t p = 0; p < order.size(); ++p) part_faces[rank[p]].reserve(faces_of[p]);
  for (size_t f = 0; f < mesh.face_count(); ++f)
    part_faces[rank[face_part[f]]].push_back(static_cast<uint32_t>(f));
  return part_faces;
}

std::vector<MeshPart> connected_parts(const PolygonMesh& mesh, const StopCheck* stop) {
  std::vector<std::vector<uint32_t>> part_faces = connected_part_faces(mesh, stop);
  std::vector<MeshPart> parts(part_faces.size());
  std::vector<uint32_t> scratch(mesh.vertex_count(), kUnreferenced);
  for (size_t k = 0; k < parts.size(); ++k) {
    parts[k] = submesh(mesh, part_faces[k], &scratch);
    std::vector<uint32_t>().swap(part_faces[k]);
  }
  return parts;
}

}  // namespace spheremap
