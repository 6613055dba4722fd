// The envelope of any asset (Reach II): from any triangles (a soup, open, non-manifold, many
// parts, any genus), a closed 2-manifold genus-0 triangle mesh around them, at about the
// offset d outside. Steps, each in its own file: the voxel grid (dense, one byte per voxel,
// capped; not a sparse narrow band), its band and the flood-filled solid
// (envelope_grid.h); a ball grown through simple points, inside the solid (handles cut)
// and, as the dual, the outside grown inward (handles filled), and, where both change
// something, a third that keeps each handle's smaller change; whichever changes fewest
// voxels is kept (envelope_topology.h); the ball's voxel
// surface (envelope_surface.h); smoothing (envelope_fit.h), reduction (envelope_reduce.h),
// fitting toward the original (envelope_fit.h); the checks (envelope_check.h).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "core/mesh/mesh.h"

namespace spheremap {

// Which change of the solid's handles is kept: the one that changes fewest voxels (the
// default), or the cut or the fill alone (tests and experiments: the cut envelope of a thin
// sheet with handles is a thin two-sided shell with slits, tests/thin_shells.h).
enum class EnvelopeRule { kFewestVoxels, kCut, kFill };

struct EnvelopeOptions {
  // Voxels across the bounding-box diagonal (h = diagonal / this). 256, not the issue's
  // 512: a 252-triangle coin took 4.5 s at 256 and 43 s at 512 on the shared 2-core
  // machine (the growth and the reduction scale with the voxels: 8x, and the voxel surface
  // 4x), so 512 is an option, not the default.
  double resolution = 256;
  // The offset d: in model units when > 0; else as a fraction of the diagonal when > 0;
  // else offset_voxels * h.
  double offset = 0;
  double offset_fraction = 0;
  double offset_voxels = 1.5;
  // The reduced surface is fitted to this many voxels from the original (its closest
  // point), or to the offset when that is smaller: the offset makes the solid (gaps closed,
  // thin parts thick enough for the grid), the fit brings the surface back toward the
  // original. Not 0: an open sheet's two sides would then coincide. 0.5, not the offset's
  // 1.5: a voxel closer to the original on every side that no handle change moved
  // (measured on the reach set's wrapped assets: BENCHMARKS.md, session 30).
  double fit_voxels = 0.5;
  // 0: the input's faces, within [20,000, 200,000]. The floor is 20,000, not less: at 2,000
  // faces the reduced envelope of small game-kit tiles cut 3-4% of the diagonal off their
  // corners (original->envelope), at 20,000 0.7%, for the same time (the map of 20,000
  // faces takes well under a second).
  size_t target_faces = 0;
  // The grid's voxels at most (counted before allocating; about 12 bytes each at the peak).
  size_t max_voxels = size_t{1} << 26;
  EnvelopeRule rule = EnvelopeRule::kFewestVoxels;
  // Threads for the two-sided distance of the report (0: all cores); the rest runs on one.
  int threads = 0;
  // false: the report's distances are left 0, for a caller that measures the envelope
  // against other faces than it was built from (a repaired part's own input faces).
  bool measure_distance = true;
};

struct EnvelopeReport {
  double diagonal = 0;  // of the input's bounding box (finite positions)
  double voxel_size = 0, offset = 0;
  double fit_distance = 0;  // min(offset, fit_voxels * voxel_size): where the surface is fitted
  int grid[3] = {0, 0, 0};
  size_t solid_voxels = 0;
  // "cut" (the ball grown inside the solid), "fill" (the outside grown inward) or "mixed"
  // (each handle's smaller change, envelope_topology.h): the one that changed fewest voxels.
  std::string rule;
  size_t handles_cut = 0, handles_filled = 0;  // 26-connected groups of voxels changed
  size_t voxels_changed = 0, largest_change_voxels = 0;
  size_t voxel_faces = 0, faces = 0;  // the voxel surface's triangles, the envelope's
  // Two-sided distance envelope <-> original (Hausdorff over every point, RMS over the
  // vertices of both: DistanceSamples::kVertices, a third of the queries), relative to
  // the original's diagonal; and each direction's largest. The envelope lies within
  // about the offset of the original except where a handle was cut or filled; the original
  // lies within about the offset of the envelope except its faces inside the solid
  // (intersecting parts, inner shells), which the envelope does not follow.
  double hausdorff = 0, rms = 0;
  double envelope_to_original = 0, original_to_envelope = 0;
};

struct Envelope {
  PolygonMesh mesh;  // triangles; closed, 2-manifold, one component, genus 0 (checked)
  EnvelopeReport report;
};

// Throws InputError: "envelope_size" (grid over max_voxels or no finite extent),
// "envelope_empty" (no triangle), "envelope_topology" (a check failed: should not happen),
// "stopped" (should_stop said so; asked throughout).
Envelope build_envelope(const PolygonMesh& input, const EnvelopeOptions& options,
                        const std::function<bool()>* should_stop = nullptr);

}  // namespace spheremap
