// Each vertex's outgoing half-edges, as the vertices they end at (compressed rows, by a
// counting sort of the corners): "is there a half-edge b -> a?" and "how many faces share
// edge {a, b}?" become scans of a vertex's few ends. The preparation asked both of every
// edge through node-based hash sets, which were most of its time on a 1.5M-triangle asset
// of 256 open parts (an allocation per edge, a cache miss per lookup).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

class HalfEdgeEnds {
 public:
  // O(vertices + corners); `mesh` may have no positions (faces alone).
  explicit HalfEdgeEnds(const PolygonMesh& mesh);

  // Half-edges a -> b (faces running from a to b); 0 for a vertex no face uses.
  size_t count(uint32_t a, uint32_t b) const;
  bool has(uint32_t a, uint32_t b) const { return count(a, b) > 0; }

  // Faces beside the undirected edge {a, b}: half-edges a -> b plus b -> a (a != b).
  size_t faces_beside(uint32_t a, uint32_t b) const { return count(a, b) + count(b, a); }

 private:
  std::vector<uint32_t> start_;  // vertex v's ends are end_[start_[v], start_[v + 1])
  std::vector<uint32_t> end_;
};

}  // namespace spheremap
