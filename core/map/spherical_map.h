// The engine's entry point: a validated genus-0 mesh in, a map onto the unit sphere out.
//
//   kCoarseToFine (default): collapse hierarchy to a tetrahedron, then per level
//     kernel-safe insertion, Lai-Cheng smoothing (10..40 iterations), local repair and a
//     fold-free fallback; bijective on every corpus mesh (ALGORITHM §B4).
//   kPaper: Lai & Cheng's own loop: pre-smoothing, projection about a weighted centroid,
//     smoothing until no fold or the iteration cap (§A2, §A3). Slow and not guaranteed;
//     kept for comparison.
//
// Never reports a folded map as a success: result.check.bijective is the verdict of the
// §B1 test on the finished map.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/map/lai_cheng.h"
#include "core/map/map_check.h"
#include "core/map/stretch_optimizer.h"
#include "core/mesh/mesh.h"

namespace spheremap {

enum class Method { kCoarseToFine, kPaper };

// Coarse-to-fine only: how far every level's map is stretch-optimized as the hierarchy
// grows (ALGORITHM §F). kStandard: to a relative energy decrease of 1e-3 per sweep;
// kFast: 1e-2 (measured: 20-35% less time, stretch 3-15% higher); kHigh: 1e-4 and 10x
// the sweeps. A map the optimized hierarchy cannot make fold-free falls back to the
// Lai-Cheng map of each level (engine v1, `optimize = false`).
enum class Quality { kFast, kStandard, kHigh };
std::string_view to_string(Quality quality);
std::optional<Quality> parse_quality(std::string_view name);  // "fast", "standard", "high"

struct MapOptions {
  Method method = Method::kCoarseToFine;
  Quality quality = Quality::kStandard;
  bool optimize = true;           // false: the Lai-Cheng map of each level only (engine v1)
  StretchOptions stretch;         // energy and per-level stop rule (scaled by the quality)
  double level_growth = 2.0;      // optimized hierarchy: levels grow by about this factor
  bool represented_area = true;   // coarse levels weigh triangles by the fine area they stand for
  double alpha = 0.0;             // limit operator parameter, 0 = Catmull-Clark
  SmoothingOptions smoothing;     // offset u, its placement, centroid relaxation, threads
  int presmooth_steps = 10;       // paper: A applied to the 3D mesh before projecting
  size_t max_iterations = 20000;  // paper: iteration cap
  size_t min_level_iterations = 10;        // both: iterations before a 0-fold stop
  size_t max_level_iterations = 40;        // coarse-to-fine: per level before local repair
  size_t max_repair_iterations = 5000;     // coarse-to-fine: local repair budget per level
  size_t safe_steps = 40;                  // coarse-to-fine: fold-safe steps of the fallback
  size_t smooth_min_vertices = 50;         // coarse-to-fine: smaller levels are only inserted
  size_t projected_start_vertices = 1000;  // coarse-to-fine: start level size (0 = tetrahedron)
  size_t direct_iterations =
      40;  // coarse-to-fine: budget of the paper's map of the whole mesh (0: skip)
  size_t projected_start_iterations = 1000;  // coarse-to-fine: smoothing budget of that start
  // Coarse-to-fine: maps tried when one folds, at most: the 4 measured (A-step weight,
  // offset) settings in a cache-friendly vertex order, then the same in the input order.
  size_t attempts = 8;
  double time_limit_seconds = 0;  // 0 = none
  // The factor on the area of the faces preparation added (hole fills, handle closings:
  // map_to_sphere's `filled`) in the stretch energy, as Praun & Hoppe's SphereParam weighs
  // them down: they get little room on the sphere, the input's faces the rest. 1: as any.
  double filled_weight = 0.1;
};

struct MapProgress {
  // "hierarchy", "project", "smooth", "repair", "fallback", "optimize", "polish", "verify"
  std::string_view stage;
  int level = 0, levels = 0;
  size_t vertices = 0;  // of the current level
  size_t iteration = 0;
  size_t folds = 0;
  double energy = 0;  // "optimize": stretch energy per unit area (1 + lambda: isometric)
  double elapsed_seconds = 0;
  // An asset of several parts (map_parts.h): the part being mapped (1-based) of how many;
  // 0 of 0 for one mesh. Each part's levels count from 0 again.
  size_t part = 0, parts = 0;
};

struct MapControl {
  std::function<void(const MapProgress&)> on_progress;  // called often: keep it cheap
  const std::atomic<bool>* cancel = nullptr;            // set to stop a running map
  // When time_limit_seconds starts counting (default: when map_to_sphere is called). The
  // command line sets its own start, so reading and preparing the input count too.
  std::optional<std::chrono::steady_clock::time_point> clock_start;
};

enum class StopReason { kBijective, kFoldsRemain, kIterationLimit, kTimeLimit, kCancelled };
std::string_view to_string(StopReason reason);

struct LevelReport {
  size_t vertices = 0;
  size_t kernel_insertions = 0;  // ring average invalid: placed by the kernel search
  size_t failed_insertions = 0;  // no valid position found
  size_t iterations = 0;
  size_t repair_iterations = 0;
  bool fallback = false;       // reverted to the last fold-free state + fold-safe sweeps
  size_t folds = 0;            // at the end of the level
  double min_area = 0;         // smallest signed spherical triangle area at the end of the level
  size_t optimize_sweeps = 0;  // standard/high: stretch optimization sweeps
  size_t newton_steps = 0;     // whole-level Newton steps after the sweeps (small levels)
  double energy = 0;           // standard/high: stretch energy per unit area at the end
};

struct MapResult {
  std::vector<Vec3> sphere;  // per mesh vertex; empty only when cancelled
  MapCheck check;
  StopReason stop_reason = StopReason::kFoldsRemain;
  size_t attempts = 0;                    // coarse-to-fine: maps tried (1 = the first succeeded)
  size_t iterations = 0;                  // smoothing iterations, all levels and attempts
  double fine_iteration_equivalents = 0;  // sum of iterations x level size / vertex count
  std::vector<LevelReport> levels;        // coarse to fine
  size_t hierarchy_rounds = 0;
  bool optimized = false;  // the stretch-optimized hierarchy made it (else the Lai-Cheng levels)
  double stretch_vertex_updates = 0;  // Newton steps of the stretch optimization
  size_t polish_rounds = 0;           // rounds of the safety net (polish_map) that ran
  size_t float32_rescued = 0;         // vertices moved so float32 rounding folds nothing
  double hierarchy_seconds = 0, mapping_seconds = 0, optimize_seconds = 0, verify_seconds = 0;
  // An asset of parts: finding and fitting copies of earlier parts (map_parts.h), whether
  // a copy was found or not (a part's fits can cost more than its map: vcglib's
  // abominevole, 47,000 slivers, spent 34 s there before copies were looked up by shape).
  double copies_seconds = 0;
  bool inward = false;  // the input faces point inward; the map keeps that orientation
  // The stage that was running when the time limit or a cancel stopped the map
  // ("hierarchy", "optimize", "repair", ...; empty when it ran to the end).
  std::string stopped_in;
};

// Precondition: mesh passed require_mappable(analyze_topology(mesh)). `filled`: triangles
// of `mesh` (by vertex ids, either orientation) that preparation added; they weigh
// options.filled_weight in the stretch energy.
MapResult map_to_sphere(const PolygonMesh& mesh, const MapOptions& options,
                        const MapControl& control = {}, std::span<const Triangle> filled = {});

// The fan triangles of the mesh, reversed when the mesh is oriented inward, so that a
// valid map has positive determinants (ALGORITHM §0.3).
struct OrientedTriangles {
  std::vector<Triangle> triangles;
  bool inward = false;
  size_t conflicting_faces = 0;
};
OrientedTriangles oriented_triangles(const PolygonMesh& mesh);

// Per triangle of `triangles`: 1 when it is one of `filled` (corners as a set, either
// orientation), else 0; empty when `filled` is.
std::vector<char> filled_mask(std::span<const Triangle> triangles,
                              std::span<const Triangle> filled);

// The mesh as the map works on it: `input`'s vertices in `order` (order[k] is the input
// vertex the k-th one was), centred and scaled to the unit ball, and its oriented fan
// triangles each rotated to its smallest vertex and sorted (canonical_triangles), so the
// map depends neither on the file's face order nor on where a face's corners start.
// Benchmarks use it to see exactly what the map sees.
struct MappingInput {
  PolygonMesh mesh;
  OrientedTriangles oriented;
};
MappingInput mapping_input(const PolygonMesh& input, const std::vector<uint32_t>& order);

}  // namespace spheremap
