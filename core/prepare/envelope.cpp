#include "core/prepare/envelope.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/input_error.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/surface_distance.h"
#include "core/mesh/triangle_tree.h"
#include "core/prepare/envelope_check.h"
#include "core/prepare/envelope_fit.h"
#include "core/prepare/envelope_grid.h"
#include "core/prepare/envelope_plan.h"
#include "core/prepare/envelope_reduce.h"
#include "core/prepare/envelope_surface.h"
#include "core/prepare/envelope_topology.h"

namespace spheremap {
namespace {

// The reduction's floor follows the envelope's size in voxels: at least one triangle per
// this many voxel-surface triangles (about 4 voxels a side), up to kFloorCap. A part's
// target from its own faces alone (a 106-triangle track tile got 256 faces) cut corners
// 2-10% of the asset's diagonal off low-poly game-kit parts (reach set, session 30).
constexpr size_t kVoxelFacesPerFace = 16, kFloorCap = 20000;

// Smoothing pairs on the voxel surface and fitting rounds on the reduced one: enough to
// take the staircase out (each pair reaches a few voxels) and settle on the offset.
constexpr int kSmoothing = 6, kFitting = 5;

// The reduced surface fitted to the offset, or an empty mesh when its checks fail.
PolygonMesh fitted(const PolygonMesh& voxels, size_t target, const TriangleTree& original, double d,
                   int threads, StopCheck& stop) {
  PolygonMesh mesh = reduce_surface(voxels, target, stop);
  stop.check();
  if (!envelope_failures(mesh).empty()) return {};
  fit_to_offset(mesh, original, d, kFitting, threads, stop);
  if (!envelope_failures(mesh).empty()) return {};
  return mesh;
}

}  // namespace

Envelope build_envelope(const PolygonMesh& input, const EnvelopeOptions& options,
                        const std::function<bool()>* should_stop) {
  StopCheck stop(should_stop);
  const EnvelopePlan plan = plan_envelope(input, options);
  const std::vector<Triangle>& triangles = plan.triangles;
  const VoxelGrid& grid = plan.grid;
  const double d = plan.d;
  Envelope out;
  EnvelopeReport& report = out.report;
  report.diagonal = plan.diagonal;
  report.voxel_size = plan.h, report.offset = d;
  report.fit_distance = plan.fit_distance;
  report.grid[0] = grid.nx, report.grid[1] = grid.ny, report.grid[2] = grid.nz;

  const std::vector<uint8_t> solid = solid_voxels(grid, input.positions, triangles, d, stop);
  report.solid_voxels = size_t(std::count(solid.begin(), solid.end(), uint8_t{1}));
  if (report.solid_voxels == 0)
    throw InputError("envelope_empty", "no voxel lies within the offset of the triangles");
  // Both growths; the one that changes fewer voxels is kept (ties: the cut, which leaves the
  // outside as it is). A cut that changed nothing (the solid is a ball already) cannot lose,
  // so the outside is not grown then: it took 29% of a 97K-triangle horse's envelope.
  BallGrowth ball = grow_ball_inside(grid, solid, stop);
  BallGrowth filled = ball.voxels_changed == 0 || options.rule == EnvelopeRule::kCut
                          ? BallGrowth{}
                          : shrink_ball_outside(grid, solid, stop);
  // With handles both ways, each handle's smaller change (envelope_topology.h) when that
  // changes fewer voxels than either rule alone.
  size_t fills_kept = 0;
  BallGrowth mixed;
  if (ball.changes > 0 && filled.changes > 0 && options.rule == EnvelopeRule::kFewestVoxels)
    mixed = grow_ball_mixed(grid, solid, ball, filled, &fills_kept, stop);
  const size_t fewest = std::min(ball.voxels_changed, filled.voxels_changed);
  report.rule =
      !mixed.ball.empty() && mixed.voxels_changed < fewest          ? "mixed"
      : options.rule == EnvelopeRule::kFill && !filled.ball.empty() ? "fill"
      : options.rule == EnvelopeRule::kFewestVoxels && filled.voxels_changed < ball.voxels_changed
          ? "fill"
          : "cut";
  if (report.rule == "fill") std::swap(ball, filled);
  if (report.rule == "mixed") std::swap(ball, mixed);
  filled = {}, mixed = {};
  if (report.rule == "mixed") {
    // Groups of changed voxels: the fills kept, the rest cuts (a fill and a cut that
    // touch count as one group, so this is at least the cuts made).
    report.handles_filled = fills_kept;
    report.handles_cut = ball.changes > fills_kept ? ball.changes - fills_kept : 0;
  } else {
    (report.rule == "cut" ? report.handles_cut : report.handles_filled) = ball.changes;
  }
  report.voxels_changed = ball.voxels_changed;
  report.largest_change_voxels = ball.largest_change;

  PolygonMesh voxels = voxel_surface(grid, ball.ball, stop);
  ball = {};
  report.voxel_faces = voxels.face_count();
  if (const std::string failures = envelope_failures(voxels); !failures.empty())
    throw InputError("envelope_topology", "the envelope's voxel surface fails: " + failures);
  smooth_surface(voxels, kSmoothing, stop);

  const TriangleTree original(input.positions, triangles);
  const size_t target =
      std::max(options.target_faces ? options.target_faces
                                    : std::clamp<size_t>(triangles.size(), 20000, 200000),
               std::min(voxels.face_count() / kVoxelFacesPerFace, kFloorCap));
  // The reduction keeps the link condition, so its checks should pass; if they do not,
  // it is tried again less far, then not at all.
  for (const size_t tried : {target, 4 * target, voxels.face_count()}) {
    out.mesh = fitted(voxels, tried, original, report.fit_distance, options.threads, stop);
    if (out.mesh.face_count() > 0) break;
  }
  if (out.mesh.face_count() == 0)
    throw InputError("envelope_topology", "the envelope's fitted surface fails its checks");
  report.faces = out.mesh.face_count();
  if (!options.measure_distance) return out;

  std::vector<Triangle> envelope_triangles(out.mesh.face_count());
  for (size_t f = 0; f < envelope_triangles.size(); ++f) {
    const auto c = out.mesh.face(f);
    envelope_triangles[f] = {c[0], c[1], c[2]};
  }
  const SurfaceDistance distance =
      surface_distance(input.positions, triangles, out.mesh.positions, envelope_triangles,
                       options.threads, should_stop, DistanceSamples::kVertices);
  report.hausdorff = distance.hausdorff;
  report.rms = distance.rms;
  report.envelope_to_original = distance.max_b_to_a;
  report.original_to_envelope = distance.max_a_to_b;
  return out;
}

}  // namespace spheremap
