#include "core/mesh/half_edge_ends.h"

#include <algorithm>

namespace spheremap {

HalfEdgeEnds::HalfEdgeEnds(const PolygonMesh& mesh) {
  // The faces' own largest index, not vertex_count(): face lists without positions (a
  // renumbering's faces) are asked too.
  const uint32_t top =
      mesh.indices.empty() ? 0 : *std::max_element(mesh.indices.begin(), mesh.indices.end()) + 1;
  start_.assign(std::max<size_t>(mesh.vertex_count(), top) + 1, 0);
  for (uint32_t v : mesh.indices) ++start_[v + 1];
  for (size_t v = 0; v + 1 < start_.size(); ++v) start_[v + 1] += start_[v];
  end_.resize(start_.back());
  std::vector<uint32_t> cursor(start_.begin(), start_.end() - 1);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k) end_[cursor[face[k]]++] = face[(k + 1) % face.size()];
  }
}

size_t HalfEdgeEnds::count(uint32_t a, uint32_t b) const {
  if (size_t{a} + 1 >= start_.size()) return 0;  // no face uses a
  return static_cast<size_t>(std::count(end_.begin() + start_[a], end_.begin() + start_[a + 1], b));
}

}  // namespace spheremap
