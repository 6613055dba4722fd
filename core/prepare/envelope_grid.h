// The voxel grid of the envelope (Reach II, step 1): a dense grid of cubes of side h over
// the input's bounding box grown by the offset and a padding, the narrow band (voxels
// whose centre is within the offset d of a triangle, exact point-triangle distance) and
// the solid (the band plus everything it encloses: not reached by a 6-connected flood
// fill of the other voxels from the grid's border).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct VoxelGrid {
  Vec3 origin;  // the low corner of voxel (0, 0, 0)
  double h = 0;
  int nx = 0, ny = 0, nz = 0;
  size_t size() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  size_t index(int x, int y, int z) const {
    return (size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x);
  }
  Vec3 center(int x, int y, int z) const {
    return origin + Vec3{(x + 0.5) * h, (y + 0.5) * h, (z + 0.5) * h};
  }
};

// Voxels on each side beyond the bounding box grown by d: the flood fill starts there and
// the topology's 3x3x3 tests never leave the grid.
inline constexpr int kGridPadding = 2;

// The grid over [lo, hi] grown by d plus the padding. Throws InputError("envelope_size")
// when it would have more than max_voxels voxels (counted before allocating) or h is not
// a positive finite length.
VoxelGrid layout_grid(const Vec3& lo, const Vec3& hi, double h, double d, size_t max_voxels);

// Per voxel 1 when its centre is within d of a triangle (the narrow band), else 0.
// Triangles with a non-finite corner are skipped. `stop` is ticked per voxel visited.
std::vector<uint8_t> band_voxels(const VoxelGrid& grid, std::span<const Vec3> positions,
                                 std::span<const Triangle> triangles, double d, StopCheck& stop);

// Turns a band (per voxel 1 or 0) into its solid: every voxel that a 6-connected flood fill
// of the other voxels from the grid's border does not reach becomes 1.
void fill_enclosed(const VoxelGrid& grid, std::vector<uint8_t>& band, StopCheck& stop);

// Per voxel 1 when solid (within d of a triangle, or enclosed by such voxels), else 0:
// band_voxels, then fill_enclosed.
std::vector<uint8_t> solid_voxels(const VoxelGrid& grid, std::span<const Vec3> positions,
                                  std::span<const Triangle> triangles, double d, StopCheck& stop);

// Per voxel the number of 6-steps to the nearest voxel whose `inside` differs, for voxels
// with inside[v] == from (others 0), capped at 65535.
std::vector<uint16_t> steps_to_other(const VoxelGrid& grid, const std::vector<uint8_t>& inside,
                                     uint8_t from, StopCheck& stop);

}  // namespace spheremap
