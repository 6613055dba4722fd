#include "core/prepare/vertex_corners.h"

#include <algorithm>

namespace spheremap {

std::optional<VertexCorners> VertexCorners::of_faces(const PolygonMesh& mesh,
                                                     std::span<const uint32_t> faces) {
  VertexCorners out;
  out.first_.assign(mesh.vertex_count() + 1, 0);
  for (uint32_t f : faces)
    for (uint32_t v : mesh.face(f)) ++out.first_[v + 1];
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (out.first_[v + 1] > 0) ++out.vertices_;
    out.first_[v + 1] += out.first_[v];
  }
  out.corners_.resize(out.first_.back());
  std::vector<uint32_t> filled(out.first_.begin(), out.first_.end() - 1);
  for (uint32_t position = 0; position < faces.size(); ++position) {
    const uint32_t f = faces[position];
    const uint32_t begin = mesh.offsets[f], size = mesh.offsets[f + 1] - begin;
    for (uint32_t k = 0; k < size; ++k) {
      const uint32_t v = mesh.indices[begin + k];
      const uint32_t next = mesh.indices[begin + (k + 1) % size];
      if (next == v) return std::nullopt;
      out.corners_[filled[v]++] = {next, mesh.indices[begin + (k + size - 1) % size], begin + k,
                                   position};
    }
  }
  // Each row by next vertex (a cone's apex has a corner per rim vertex: found by bisection);
  // two corners of one vertex with the same next vertex are an edge run twice the same way.
  const auto by_next = [](const VertexCorner& a, const VertexCorner& b) { return a.next < b.next; };
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto begin = out.corners_.begin() + out.first_[v],
               end = out.corners_.begin() + out.first_[v + 1];
    std::sort(begin, end, by_next);
    if (std::adjacent_find(begin, end, [](const VertexCorner& a, const VertexCorner& b) {
          return a.next == b.next;
        }) != end)
      return std::nullopt;
  }
  return out;
}

std::span<const VertexCorner> VertexCorners::at(uint32_t v) const {
  if (v + size_t{1} >= first_.size()) return {};
  return {corners_.data() + first_[v], corners_.data() + first_[v + 1]};
}

const VertexCorner* VertexCorners::find(uint32_t a, uint32_t b) const {
  const std::span<const VertexCorner> row = at(a);
  const auto it =
      std::lower_bound(row.begin(), row.end(), b,
                       [](const VertexCorner& c, uint32_t next) { return c.next < next; });
  return it != row.end() && it->next == b ? &*it : nullptr;
}

}  // namespace spheremap
