// The triangles of a hierarchy level while its vertices are inserted one by one, so a
// map can be optimized between two insertions (core/map/coarse_to_fine.cpp, insertions
// retried). Inserting u (collapsed into v, oriented ring r_i) undoes the collapse: v's
// triangles (v, r_i, r_i+1) inside the ring become (u, r_i, r_i+1), and the two star
// triangles at v come back.
#pragma once

#include <map>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

class PartialLevel {
 public:
  // `coarser`: the triangles of the level the insertions start from.
  explicit PartialLevel(std::span<const Triangle> coarser);

  std::span<const Triangle> triangles() const { return triangles_; }

  // Throws std::logic_error when a triangle (v, r_i, r_i+1) is missing (not a collapse
  // record of this mesh).
  void split(uint32_t u, uint32_t v, std::span<const uint32_t> ring);

 private:
  std::vector<Triangle> triangles_;
  std::map<Triangle, uint32_t> index_;  // each triangle rotated to its smallest vertex
};

}  // namespace spheremap
