// The half-edge collapse hierarchy (ALGORITHM §B4.1, PROTOTYPE-FINDINGS §6 step 1).
//
// Vertices are removed by collapses u -> v in rounds down to a tetrahedron. Each round
// collapses an independent set (no two collapses touch the same 1-ring), cheapest first
// by quadric error (collapse_cost.h); a collapse must pass the link condition |ring(u) ∩ ring(v)| =
// 2 and, until a round accepts nothing, must not flip or degenerate the 3D triangles around u.
// Rounds are grouped into levels of about level_growth x vertices (4 by default).
//
// Vertices are renumbered so that every level is a prefix: new ids 0..3 are the
// tetrahedron, then vertices in reverse removal order. Level l holds new ids
// [0, level_sizes[l]); inserting ids in ascending order undoes the collapses.
#pragma once

#include <functional>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

struct CollapseHierarchy {
  std::vector<uint32_t> new_to_old;   // new id -> input vertex
  std::vector<uint32_t> old_to_new;   // input vertex -> new id
  std::vector<uint32_t> level_sizes;  // ascending: 4, ..., vertex count
  // Triangles of every level but the finest, in new ids (the finest level is the input).
  std::vector<std::vector<Triangle>> level_triangles;
  // For new id u >= 4: the vertex it collapsed into, and its ring as an oriented cycle
  // r_0..r_k-1 (new ids): the star triangles are (u, r_i, r_i+1).
  std::vector<uint32_t> collapse_target;
  std::vector<uint32_t> ring_offsets;
  std::vector<uint32_t> rings;
  size_t rounds = 0;
  size_t round_geometry_dropped = 0;  // first round without the 3D normal test (0: never)

  std::span<const uint32_t> ring(uint32_t u) const {
    return {rings.data() + ring_offsets[u], ring_offsets[u + 1] - ring_offsets[u]};
  }
};

// Thrown by build_hierarchy when `should_stop` says so (a time limit, a cancel).
class HierarchyStopped : public std::runtime_error {
 public:
  HierarchyStopped() : std::runtime_error("hierarchy: stopped before the tetrahedron") {}
};

// Precondition: triangles form a closed, connected, oriented genus-0 manifold with at
// least 4 vertices. Throws std::runtime_error if no collapse is possible (cannot happen
// on such input: every triangulated sphere but the tetrahedron has a contractible edge).
// level_growth: vertices of a level over those of the next coarser one (about).
// should_stop (may be empty) is asked every few thousand vertices: ~3 s of rounds on 1.3M
// triangles had no way to stop.
// threads: for the re-keying of each round (0 = all cores); the hierarchy is the same for
// any value.
CollapseHierarchy build_hierarchy(std::span<const Vec3> positions,
                                  std::span<const Triangle> triangles, double level_growth = 4.0,
                                  const std::function<bool()>& should_stop = {}, int threads = 0);

}  // namespace spheremap
