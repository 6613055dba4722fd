// Which holes to leave for their part's back (Reach II, prepare=auto): a part that is genus
// 0 and open (a hand open at the wrist, a head at the neck, a pipe open at both ends) whose
// holes are small enough to fill (under max_hole_fill of its surface) is still better
// closed by its own back (cut into a disc first when it has several holes:
// open_part_cuts.h, sheet_doubling.h) where a fill would stand far from it: the fill is a
// cap as far from the part as the hole is wide, which a remesh through it misses by, where
// the back lies on the part (odedstein's hand_lowres: remesh at 128 within 9.0% of the
// input with its wrist filled, 0.93% doubled).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {

// Made on a welded mesh before its holes are filled (its faces then are the part's own);
// the mesh must outlive it and may grow (fills appended) while it is asked.
class FarHoleFills {
 public:
  // `max_distance`: over the part's bounding-box diagonal. O(1): the parts are found when
  // first asked (O(vertices + corners)), among the faces the mesh had here.
  FarHoleFills(const PolygonMesh& mesh, double max_distance);

  // Whether the hole `loop` (a boundary loop of the mesh, as hole_filling.h finds them) is
  // a hole of a part that is or can be cut into a disc (can_become_disc, open_part_cuts.h),
  // or is open with handles (which hole_cones.h and the handle cuts make one), whose `fill`
  // (triangles over the loop's corners) has a point farther than max_distance from the part's own
  // faces (points spread on each fill triangle, measured to a triangle tree of the part, built when
  // first asked).
  bool operator()(std::span<const uint32_t> loop, std::span<const Triangle> fill) const;

 private:
  void find_parts() const;

  const PolygonMesh& mesh_;
  double max_distance_;
  size_t own_faces_;
  mutable bool found_ = false;
  mutable std::vector<uint32_t> part_of_;  // per vertex: its open sphere (kNone: in none)
  // Per open sphere: its faces as a tree (built when one of its holes is first asked: a
  // scan has dozens), and its bounding-box diagonal.
  mutable std::vector<PolygonMesh> parts_;
  mutable std::vector<std::optional<TriangleTree>> trees_;
  mutable std::vector<double> diagonals_;
};

}  // namespace spheremap
