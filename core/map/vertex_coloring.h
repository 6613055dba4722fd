// Greedy vertex colouring of a triangle mesh's edge graph, for lock-free parallel
// vertex updates: no two vertices of a class share a triangle, so moving one class at a
// time on all threads touches every star from one thread only.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

// Classes of vertex ids (ascending within a class), colours in first-use order;
// deterministic. Vertices in no triangle get colour 0. At most max valence + 1 classes.
std::vector<std::vector<uint32_t>> color_classes(std::span<const Triangle> triangles, size_t n);

}  // namespace spheremap
