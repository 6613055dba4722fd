// Welding vertices by position (ALGORITHM §0.1). glTF splits vertices along UV seams
// and hard normals, so a closed surface arrives with boundaries until welded.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

inline constexpr uint32_t kUnreferenced = std::numeric_limits<uint32_t>::max();

struct WeldResult {
  PolygonMesh mesh;                       // referenced vertices only, first-occurrence order
  std::vector<uint32_t> input_to_welded;  // per input vertex; kUnreferenced if no face uses it
  size_t unreferenced_vertices = 0;
};

// tolerance = 0 welds exactly equal positions; > 0 welds positions closer than
// tolerance * (bounding-box diagonal). Non-finite positions are never welded.
// For an input without duplicates or unreferenced vertices the order is unchanged.
// `stop` (optional) is ticked as it goes: it may end the weld with InputError("stopped").
WeldResult weld(const PolygonMesh& input, double relative_tolerance = 0.0,
                StopCheck* stop = nullptr);

// Drops the welded vertices that no face uses any more (a step removed faces), the others
// renumbered in order, in the faces and in input_to_welded (an input vertex of a dropped
// one becomes kUnreferenced: callers first move every input corner to a vertex its welded
// face uses). Keeps the invariant above: the map cannot collapse a vertex of no face.
// Returns how many were dropped. O(vertices + corners).
size_t drop_unused_vertices(WeldResult& welded);

}  // namespace spheremap
