// The remesh grid and texture of each part of an asset of several parts.
//
// Samples per unit area stay alike across parts: the asked resolution N for the largest
// part, smaller parts in proportion to the square root of their area. A long thin part
// (a rod, a cable, a frame) has little area for its length, and a grid's error follows the
// length its samples span, not the area: a curtain rail of 1/1000 of a room's area got a
// 4 x 4 grid and stood 1.04 model units (4.6% of the room's diagonal) from its remesh. So a
// part's grid is also at least N times its bounding-box diagonal over the largest one's.
// That alone is
// unbounded in the number of parts: 500 equal quads at N = 256 asked for 500 full grids
// (33M samples, 7.8 GB), from a 20 KB file, where a job's memory charge counts one grid.
// So the grids together hold at most kPartSampleBudget grids of N's samples; past that
// every part's grid shrinks by one factor, down to the octahedron's own (N = 2), and only
// the count of parts (at 9 samples each) can go past the budget.
#pragma once

#include <span>
#include <vector>

namespace spheremap {

// The most samples the parts' grids hold together, in grids of the asked resolution.
inline constexpr double kPartSampleBudget = 4;

// Per part (areas: each part's surface area; diagonals: its bounding-box diagonal; both in
// the same order, any order), its grid: quads per side, even, at most `resolution` and at
// least min(8, resolution) while the budget allows, 2 past it.
// Precondition: resolution >= 2 and even; diagonals empty (area rule alone) or one per area.
// O(parts), times 50 when the budget binds.
std::vector<int> part_grids(int resolution, std::span<const double> areas,
                            std::span<const double> diagonals = {});

// The side of a remesh's baked textures (base colour, normal map) at a grid of `resolution`
// quads: a texel per half quad, within 256..2048 px.
int remesh_texture_size(int resolution);

// The smallest texture side a part gets.
inline constexpr int kMinPartTexture = 16;

// The texture side of a part whose grid is `grid` when `resolution` was asked: the whole
// mesh's side scaled by grid / resolution, at least kMinPartTexture. Texels per unit area
// then stay alike across parts, as samples do, and fall under the same budget: a side of
// 256 per part was 3,534 textures of 64K texels (a 64 MB remesh) for a city of small parts.
int part_texture_size(int resolution, int grid);

}  // namespace spheremap
