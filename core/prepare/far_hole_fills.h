// Which holes to leave for their part's back (Reach II, prepare=auto): a part that is a
// disc whose one hole is small enough to fill (a hand open at the wrist, a head at the neck,
// under max_hole_fill of its surface) is still better closed by its own back
// (sheet_doubling.h) when the fill would stand far from it: the fill is a cap as far from
// the part as the hole is wide, which a remesh through it misses by, where the back lies on
// the part (odedstein's hand_lowres: remesh at 128 within 9.0% of the input with its wrist
// filled, 0.93% doubled).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

// Made on a welded mesh before its holes are filled (its faces then are the part's own);
// the mesh must outlive it and may grow (fills appended) while it is asked.
class FarDiscFills {
 public:
  // `max_distance`: over the part's bounding-box diagonal. O(1): the parts are counted
  // when first asked (O(vertices + corners)), on the faces the mesh had here.
  FarDiscFills(const PolygonMesh& mesh, double max_distance);

  // Whether the hole `loop` (a boundary loop of the mesh, as hole_filling.h finds them) is
  // the one hole of a disc (Euler characteristic 1) whose `fill` (triangles over the loop's
  // corners) has a point farther than max_distance from the part's own faces (points spread
  // on each fill triangle, measured to a triangle tree of the part, built when asked).
  bool operator()(std::span<const uint32_t> loop, std::span<const Triangle> fill) const;

 private:
  void count_parts() const;

  const PolygonMesh& mesh_;
  double max_distance_;
  size_t own_faces_;
  mutable bool counted_ = false;
  mutable std::vector<uint32_t> part_of_;       // per vertex: its part (kNone: in no face)
  mutable std::vector<long long> euler_;        // per part: V - E + F
  mutable std::vector<size_t> boundary_edges_;  // per part
  // Per part: its faces are faces_[first_face_[p], first_face_[p + 1]).
  mutable std::vector<uint32_t> first_face_, faces_;
};

}  // namespace spheremap
