// Thin closed plates as exporters write them (issue "Reach I" item 6): an outline
// extruded by a small fraction of its size, side quads split into two triangles, each cap
// triangulated without interior vertices (a fan from one outline vertex, or ear clipping),
// so the caps are full of long sliver triangles, down to ~1e-6 of the median area.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap::testing {

enum class CapTriangulation {
  kFan,      // every cap triangle shares outline vertex 0 (convex outlines only)
  kEarClip,  // ears clipped walking round the outline, as simple exporters do
};

// The prism over `outline` (counter-clockwise, simple), z from -thickness / 2 to
// thickness / 2, all triangles, outward.
PolygonMesh thin_plate(std::span<const std::array<double, 2>> outline, double thickness,
                       CapTriangulation caps);

// Outlines about 2 across. points: how many outline vertices.
std::vector<std::array<double, 2>> circle_outline(int points);
std::vector<std::array<double, 2>> rounded_rectangle_outline(int points_per_corner);
std::vector<std::array<double, 2>> leaf_outline(int points);
std::vector<std::array<double, 2>> heart_outline(int points);

// The plates: a coin (fan caps), a card (rounded corners), a leaf and a heart (ear-clipped
// caps; the heart is the reported shape's size: 4,285 outline points, 17,136 triangles),
// each 1e-3 of its diameter thick.
std::vector<NamedMesh> thin_plates();

}  // namespace spheremap::testing
