#include "core/prepare/corner_map.h"

#include "core/prepare/hole_filling.h"  // directed_edge_key

namespace spheremap {
namespace {

bool add_face(const PolygonMesh& mesh, uint32_t f, CornerMap& map) {
  const uint32_t first = mesh.offsets[f], size = mesh.offsets[f + 1] - first;
  for (uint32_t k = 0; k < size; ++k) {
    const uint32_t a = mesh.indices[first + k], b = mesh.indices[first + (k + 1) % size];
    if (a == b || !map.emplace(directed_edge_key(a, b), first + k).second) return false;
  }
  return true;
}

}  // namespace

std::optional<CornerMap> corner_map(const PolygonMesh& mesh, std::span<const uint32_t> faces) {
  size_t corners = 0;
  for (uint32_t f : faces) corners += mesh.offsets[f + 1] - mesh.offsets[f];
  CornerMap map;
  map.reserve(corners);
  for (uint32_t f : faces)
    if (!add_face(mesh, f, map)) return std::nullopt;
  return map;
}

std::optional<CornerMap> corner_map(const PolygonMesh& mesh) {
  CornerMap map;
  map.reserve(mesh.indices.size());
  for (uint32_t f = 0; f < mesh.face_count(); ++f)
    if (!add_face(mesh, f, map)) return std::nullopt;
  return map;
}

}  // namespace spheremap
