#include "core/mesh/submesh.h"

namespace spheremap {

MeshPart submesh(const PolygonMesh& mesh, std::span<const uint32_t> faces,
                 std::vector<uint32_t>* scratch) {
  std::vector<uint32_t> own;
  if (!scratch) own.assign(mesh.vertex_count(), kUnreferenced);
  std::vector<uint32_t>& local = scratch ? *scratch : own;
  MeshPart part;
  std::vector<uint32_t> corners;
  for (uint32_t f : faces) {
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
  for (uint32_t v : part.vertex) local[v] = kUnreferenced;  // scratch back to unused
  return part;
}

std::vector<Triangle> kept_triangles(std::span<const Triangle> triangles,
                                     std::span<const char> left_out) {
  if (left_out.empty()) return {triangles.begin(), triangles.end()};
  std::vector<Triangle> kept;
  kept.reserve(triangles.size());
  for (size_t k = 0; k < triangles.size(); ++k)
    if (!left_out[k]) kept.push_back(triangles[k]);
  return kept;
}

void erase_faces(PolygonMesh& mesh, std::span<const char> removed) {
  uint32_t corner = 0, face = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (removed[f]) continue;
    const uint32_t begin = mesh.offsets[f], end = mesh.offsets[f + 1];
    mesh.offsets[face++] = corner;  // face <= f: offsets[f + 1] is still to be read
    for (uint32_t s = begin; s < end; ++s) mesh.indices[corner++] = mesh.indices[s];
  }
  mesh.offsets[face] = corner;
  mesh.offsets.resize(face + 1);
  mesh.indices.resize(corner);
}

}  // namespace spheremap
