// The corners of a set of faces, vertex by vertex: per corner its slot (index into
// mesh.indices), its face's position in the set and the vertices after and before it in
// that face. The corner of a in the face running a -> b is found by bisecting a's corners
// (sorted by the vertex after them). What corner_map.h answers, without hashing: for passes over a
// whole part that are made again after every handle cut (handle_closing: a cave of 593K faces and
// 15 handles spent 0.8 s per handle building and walking a corner map).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

struct VertexCorner {
  uint32_t next = 0, prev = 0;  // the vertices after and before it in its face
  uint32_t slot = 0;            // index into mesh.indices
  uint32_t face = 0;            // position of its face in the set
};

class VertexCorners {
 public:
  // Nothing when two faces run the same way along an edge (inconsistent orientation or a
  // non-manifold edge) or a face repeats a vertex in a row, as corner_map. O(corners +
  // mesh vertices).
  static std::optional<VertexCorners> of_faces(const PolygonMesh& mesh,
                                               std::span<const uint32_t> faces);

  // v's corners by their next vertex (empty for a vertex the set does not use).
  std::span<const VertexCorner> at(uint32_t v) const;
  // The corner of a in the face running a -> b; null when there is none.
  const VertexCorner* find(uint32_t a, uint32_t b) const;
  size_t corners() const { return corners_.size(); }
  size_t vertices() const { return vertices_; }  // with at least one corner
  size_t vertex_capacity() const { return first_.empty() ? 0 : first_.size() - 1; }

 private:
  std::vector<uint32_t> first_;  // v's corners: corners_[first_[v], first_[v + 1])
  std::vector<VertexCorner> corners_;
  size_t vertices_ = 0;
};

}  // namespace spheremap
