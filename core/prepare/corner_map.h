// The corners of a set of faces by directed edge, for the cuts that walk a part's faces
// around a vertex (open_part_cuts, handle_closing): a -> b gives the slot (index into
// mesh.indices) of a in the face running a -> b; the face running b -> a is the neighbour
// across that edge, and the corner before a in its face turns about a to the next face.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>

#include "core/mesh/mesh.h"

namespace spheremap {

// directed_edge_key(a, b) -> the slot of a in the face running a -> b.
using CornerMap = std::unordered_map<uint64_t, uint32_t>;

// The corner map of `faces` of `mesh`, built in their order. Nothing when two faces run
// the same way along an edge (inconsistent orientation or a non-manifold edge) or a face
// repeats a vertex in a row. O(corners) expected.
std::optional<CornerMap> corner_map(const PolygonMesh& mesh, std::span<const uint32_t> faces);

// The same over every face of `mesh`.
std::optional<CornerMap> corner_map(const PolygonMesh& mesh);

}  // namespace spheremap
