// Genus 0 by construction (Reach II, step 2): a region grown voxel by voxel, each added only
// when it is a simple point (Bertrand's topological numbers: adding it changes neither the
// region's topology, 26-adjacency, nor its complement's, 6-adjacency) and when the region
// stays well-composed (Latecki: no two voxels of a 2x2 square or a 2x2x2 cube meet only
// along an edge or at a corner with the other kind all around). The region stays a
// topological ball whose union of closed cubes has a 2-manifold sphere as its boundary.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/mesh/stop_check.h"
#include "core/prepare/envelope_grid.h"

namespace spheremap {

// A 3x3x3 neighbourhood as bits: bit (dx + 1) + 3 (dy + 1) + 9 (dz + 1) for the voxel at
// offset (dx, dy, dz); bit 13 is the centre.
inline constexpr int kCentreBit = 13;

// Whether the centre is a simple point of the set given by `neighbourhood` (the centre's
// own bit ignored): T26(set) == 1 and T6(complement) == 1.
bool is_simple_point(uint32_t neighbourhood);

// Whether the 8 2x2x2 cubes around the centre have no critical configuration with the
// centre in the set (the rest of the neighbourhood as given).
bool stays_well_composed(uint32_t neighbourhood);

// The ball kept by one growth and what it changed against the solid.
struct BallGrowth {
  std::vector<uint8_t> ball;  // per voxel 1 inside the ball
  size_t voxels_changed = 0;  // solid voxels left out plus others taken in
  size_t changes = 0;         // 26-connected groups of changed voxels (handles cut or filled)
  size_t largest_change = 0;  // voxels of the largest group
};

// From the deepest solid voxel outward in order of depth (6-steps to the outside), only
// through solid voxels: handles are cut where the solid is thinnest; parts not reached
// are dropped (they count as changed).
BallGrowth grow_ball_inside(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                            StopCheck& stop);

// The dual: the outside grown from the grid's border inward, farthest from the solid
// first, only through non-solid voxels; the ball is what it leaves, so handles are filled
// and separate parts joined by what could not be removed between them.
BallGrowth shrink_ball_outside(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                               StopCheck& stop);

// Per handle, the smaller change (a rule close to it): each 26-connected group of voxels
// that `filled` adds to the solid is kept when it is smaller than the groups that `cut`
// removes next to it (a handle's cut runs across the handle, and its fill, a disc spanning
// the handle's hole, meets the handle all along, so the two groups of one handle touch);
// the ball is then grown inside the solid with those fills, which cuts the handles whose
// fill was not kept. A ball by construction, like the other two. Its changes are counted
// against `solid`; `fills_kept` (when given) is set to the fills kept. The caller keeps
// it only where it changes fewer voxels than the cut or the fill alone.
BallGrowth grow_ball_mixed(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                           const BallGrowth& cut, const BallGrowth& filled, size_t* fills_kept,
                           StopCheck& stop);

}  // namespace spheremap
