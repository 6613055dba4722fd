// The envelope's first step alone (envelope.h): which triangles it wraps, its voxel size,
// offset and grid, counted before anything is allocated. build_envelope starts with it; the
// server's intake asks it alone, to refuse a grid over its cap at once and to size the job's
// memory, and leaves the envelope itself to the job's worker.
#pragma once

#include <vector>

#include "core/mesh/mesh.h"
#include "core/prepare/envelope.h"
#include "core/prepare/envelope_grid.h"

namespace spheremap {

struct EnvelopePlan {
  std::vector<Triangle> triangles;  // the input's (fan) triangles with finite corners
  double diagonal = 0;              // of their bounding box
  double h = 0, d = 0;              // voxel size and offset
  double fit_distance = 0;          // min(d, fit_voxels * h)
  VoxelGrid grid;
};

// Throws InputError "envelope_empty" (no triangle) or "envelope_size" (no finite extent, a
// resolution under 1, a grid over options.max_voxels), as build_envelope does.
EnvelopePlan plan_envelope(const PolygonMesh& input, const EnvelopeOptions& options);

// Bytes an envelope of `voxels` voxels holds at its peak: the solid, the growths' per-voxel
// state and distances. Measured (spheremap map --prepare wrap, GNU time, a 9,216-triangle
// torus, 2026-11-27): 60 MB peak at 1.92M voxels, 118 MB at 5.94M, so 14.6 bytes a voxel
// more; rounded up.
inline size_t envelope_peak_bytes(size_t voxels) {
  return 16 * voxels;
}

}  // namespace spheremap
