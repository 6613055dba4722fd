#include "cli/map_options.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cli/commands.h"
#include "core/io/mesh_file.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"
#include "core/outputs/report_json.h"

namespace spheremap::cli {

const std::set<std::string> kMapValueOptions = {"method",
                                                "alpha",
                                                "offset",
                                                "offset-placement",
                                                "presmooth",
                                                "max-iterations",
                                                "min-iterations",
                                                "level-iterations",
                                                "repair-iterations",
                                                "safe-steps",
                                                "limit-weight",
                                                "attempts",
                                                "time-limit",
                                                "threads",
                                                "weld-tolerance",
                                                "prepare",
                                                "max-hole-fill",
                                                "max-handle-cycle",
                                                "wrap-resolution",
                                                "wrap-offset",
                                                "wrap-faces",
                                                "sweep",
                                                "start-vertices",
                                                "smooth-vertices",
                                                "direct-iterations",
                                                "quality",
                                                "stretch-lambda",
                                                "stretch-sweeps"};
const std::set<std::string> kMapFlags = {"no-centroid", "largest-component", "no-optimize"};

const char* const kMapOptionsHelp = R"(Mapping options:
  --quality Q               standard (default): every level of the hierarchy stretch-optimized
                            as it grows (Praun-Hoppe quality at a fraction of its time); fast:
                            a 10x looser stop rule (20-50% less time, stretch 1-20% higher);
                            high: optimized further (about 3x the time, lower stretch)
  --no-optimize             map each level by Lai-Cheng smoothing only (engine v1: thin parts
                            squeezed, often not float32-safe; the automatic fallback)
  --stretch-lambda L        weight of the inverse-stretch term, in [0, 10]
                            (default 0.1; 1 = symmetric Dirichlet)
  --stretch-sweeps N        optimization sweeps per level at most (default 60; x10 for
                            high)
  --method NAME             coarse-to-fine (default): the collapse hierarchy, each level
                            inserted kernel-safe and stretch-optimized (see --quality);
                            paper: Lai & Cheng's own loop (slow, may not reach 0 folds; for
                            comparison)
  Lai-Cheng smoothing (--method paper, --no-optimize and the fallback):
  --alpha A                 limit-operator parameter in [0, 1] (default 0 = Catmull-Clark)
  --offset U                offset (momentum) weight u in [0, 0.5] (default 0.25)
  --limit-weight W          weight of the A-step, X = P((1-W) Q + W A Q), in [0, 1] (default
                            0.5 for coarse-to-fine: less squeezing of long limbs; 1 for paper)
  --attempts N              coarse-to-fine: when a map still folds, retry up to N maps in all:
                            the 4 measured (limit weight, offset) settings, then the same in
                            the input's own vertex order (default 8)
  --offset-placement P      after: after the centroid move (default for coarse-to-fine; fewer
                            iterations, no stuck fixed points); paper: between the A-step and the
                            centroid move (default for --method paper)
  --sweep ORDER             jacobi (default: parallel, every vertex reads the previous
                            iterate) or gauss-seidel (serial, reads fresh neighbours)
  --no-centroid             disable the centroid relaxation (the paper's acceleration b)
  --presmooth N             paper: A-steps on the 3D mesh before projecting (default 10)
  --max-iterations N        paper: iteration cap (default 20000)
  --min-iterations N        iterations before a 0-fold state may stop a level (default 10)
  --level-iterations N      coarse-to-fine: smoothing iterations per level before local
                            repair (default 40)
  --repair-iterations N     coarse-to-fine: local repair budget per level (default 5000)
  --safe-steps N            coarse-to-fine: fold-safe smoothing steps of the fallback
                            (default 40)
  --direct-iterations N     coarse-to-fine: first try the paper's map of the whole mesh with
                            this many iterations, kept when bijective (default 40; 0 = skip)
  --start-vertices N        coarse-to-fine: start from the paper's projection on the largest
                            level of at most N vertices when it reaches 0 folds there, else
                            from a tetrahedron (default 1000; 0 = always the tetrahedron)
  --smooth-vertices N       coarse-to-fine: levels below N vertices are only inserted, not
                            smoothed (default 50); the finest level is always smoothed
  --time-limit S            stop after S seconds, counted from the start of reading, and
                            report what was reached and the stage stopped in (default: none)
  --threads N               worker threads (default 0 = all cores); results are bit-identical
                            for any value
  --weld-tolerance T        weld vertices closer than T x bounding-box diagonal (default 0:
                            only exactly equal positions)
  --largest-component       keep only the connected part with the most faces (default: several
                            parts are an error that lists their sizes)
  --prepare M               auto (default): every part served, exactly where it can be: as
                            parts, then each part that is an open disc (one hole too large
                            to fill) is closed by its own back, a copy facing the other way
                            (exact; metrics.preparation.sheets_doubled; a genus-0 part with
                            several such holes is cut into a disc first, along short seams:
                            open_parts_cut), then each part
                            that still cannot map is replaced by its
                            own envelope (as wrap; same voxel size and offset for all parts;
                            "wrapped" in its metrics.parts entry, with the reason and its
                            distances); a mesh of one part that cannot map is wrapped whole.
                            metrics.preparation.decided: exact, repair, parts, parts+wrap
                            or wrap.
                            parts: repair, then map every part (connected component)
                            that is closed genus 0 on a sphere of its own, each drawn where
                            its part is; parts that cannot map are left out and listed with
                            their reasons in the metrics ("parts").
                            repair: drop faces the weld collapses and duplicate (double-sided)
                            faces, make each part's orientation consistent, split
                            non-manifold vertices (one per fan); no vertex moves,
                            and a mesh that needs none of it is untouched; one part only.
                            exact: map the input as it is or refuse it.
                            wrap: map the envelope of the whole asset instead: a closed genus-0
                            mesh around it at a small offset (any input: a soup, open,
                            non-manifold, many parts, any genus; handles are cut or filled,
                            whichever changes fewer voxels); every output shows the envelope
                            (the sphere's "original" layout is the envelope's own); the
                            remesh bakes the input's base colour by closest point and says
                            its distance_to_original. metrics.preparation says what changed
                            and how far the envelope is from the input
  --wrap-resolution R       wrap: voxels across the bounding-box diagonal (default 256)
  --wrap-offset D           wrap: the envelope's offset, as a fraction of the bounding-box
                            diagonal (default 1.5 voxels)
  --wrap-faces N            wrap: the envelope's triangles at most (default the input's,
                            within 20,000 and 200,000)
  --max-hole-fill F         repair and parts close each hole whose least-area fill is at most
                            F of the surface area (default 0.05; 0: none) with triangles over
                            its own corners (no vertex added or moved); the sphere in the
                            original layout leaves the fills out, the remesh keeps them
  --max-handle-cycle L      repair and parts close each handle (genus > 0) of a closed part
                            along a non-separating cycle of at most L times the part's
                            bounding-box diagonal (default 1.5; 0: none), the shortest whose
                            fill stays within 1% of the part, else the nearest: the cut's
                            vertices are copied and both sides filled like holes
)";

void read_map_options(const Arguments& args, PrepareOptions& prepare, MapOptions& options) {
  const std::string method = args.text("method", "coarse-to-fine");
  if (method == "paper") {
    options.method = Method::kPaper;
    options.smoothing.placement = OffsetPlacement::kPaper;
  } else if (method != "coarse-to-fine") {
    throw UsageError("--method must be coarse-to-fine or paper, got '" + method + "'");
  }
  const std::string placement = args.text("offset-placement", "");
  if (placement == "after")
    options.smoothing.placement = OffsetPlacement::kAfterCentroid;
  else if (placement == "paper")
    options.smoothing.placement = OffsetPlacement::kPaper;
  else if (!placement.empty())
    throw UsageError("--offset-placement must be after or paper, got '" + placement + "'");

  const std::string quality = args.text("quality", "standard");
  if (auto q = parse_quality(quality))
    options.quality = *q;
  else
    throw UsageError("--quality must be fast, standard or high, got '" + quality + "'");
  options.optimize = !args.flag("no-optimize");
  options.stretch.lambda = args.number("stretch-lambda", options.stretch.lambda, 0, 10);
  options.stretch.max_sweeps = static_cast<size_t>(args.integer(
      "stretch-sweeps", static_cast<long long>(options.stretch.max_sweeps), 1, 100000));
  const std::string sweep = args.text("sweep", "jacobi");
  if (sweep != "jacobi" && sweep != "gauss-seidel")
    throw UsageError("--sweep must be jacobi or gauss-seidel, got '" + sweep + "'");
  options.smoothing.gauss_seidel = sweep == "gauss-seidel";
  options.alpha = args.number("alpha", options.alpha, 0, 1);
  options.smoothing.offset = args.number("offset", options.smoothing.offset, 0, 0.5);
  options.smoothing.centroid_relaxation = !args.flag("no-centroid");
  options.smoothing.threads = static_cast<int>(args.integer("threads", 0, 0, 1024));
  options.presmooth_steps =
      static_cast<int>(args.integer("presmooth", options.presmooth_steps, 0, 1000));
  options.max_iterations = static_cast<size_t>(
      args.integer("max-iterations", static_cast<long long>(options.max_iterations), 0, 100000000));
  options.min_level_iterations = static_cast<size_t>(args.integer(
      "min-iterations", static_cast<long long>(options.min_level_iterations), 0, 100000));
  options.max_level_iterations = static_cast<size_t>(args.integer(
      "level-iterations", static_cast<long long>(options.max_level_iterations), 0, 100000));
  options.max_repair_iterations = static_cast<size_t>(args.integer(
      "repair-iterations", static_cast<long long>(options.max_repair_iterations), 0, 10000000));
  options.safe_steps = static_cast<size_t>(
      args.integer("safe-steps", static_cast<long long>(options.safe_steps), 0, 100000));
  options.time_limit_seconds = args.number("time-limit", 0, 0, 1e9);
  options.smooth_min_vertices = static_cast<size_t>(args.integer(
      "smooth-vertices", static_cast<long long>(options.smooth_min_vertices), 0, 100000000));
  options.projected_start_vertices = static_cast<size_t>(args.integer(
      "start-vertices", static_cast<long long>(options.projected_start_vertices), 0, 100000000));
  options.smoothing.limit_weight =
      args.number("limit-weight",
                  options.method == Method::kPaper ? 1.0 : options.smoothing.limit_weight, 0, 1);
  options.direct_iterations = static_cast<size_t>(args.integer(
      "direct-iterations", static_cast<long long>(options.direct_iterations), 0, 100000));
  options.attempts = static_cast<size_t>(
      args.integer("attempts", static_cast<long long>(options.attempts), 1, 100));
  prepare.weld_tolerance = args.number("weld-tolerance", 0, 0, 1);
  prepare.largest_component = args.flag("largest-component");
  prepare.max_hole_fill = args.number("max-hole-fill", prepare.max_hole_fill, 0, 1);
  prepare.max_handle_cycle = args.number("max-handle-cycle", prepare.max_handle_cycle, 0, 1000);
  prepare.method = parse_prepare_method(args.text("prepare", "auto"));
  prepare.envelope.resolution =
      args.number("wrap-resolution", prepare.envelope.resolution, 8, 4096);
  prepare.envelope.offset_fraction = args.number("wrap-offset", 0, 0, 0.25);
  prepare.envelope.target_faces = static_cast<size_t>(args.integer("wrap-faces", 0, 0, 10000000));
  prepare.envelope.threads = options.smoothing.threads;  // --threads bounds the wrap too
}

PrepareMethod parse_prepare_method(const std::string& name) {
  if (name == "exact") return PrepareMethod::kExact;
  if (name == "repair") return PrepareMethod::kRepair;
  if (name == "parts") return PrepareMethod::kParts;
  if (name == "wrap") return PrepareMethod::kWrap;
  if (name == "auto") return PrepareMethod::kAuto;
  throw UsageError("--prepare must be exact, repair, parts, wrap or auto, got '" + name + "'");
}

// Progress lines on stderr once a run has taken a second, at most twice a second.
MapControl progress_printer(bool quiet, double& last_print) {
  MapControl control;
  if (quiet) return control;
  control.on_progress = [&last_print](const MapProgress& p) {
    if (p.elapsed_seconds < 1.0 || p.elapsed_seconds - last_print < 0.5) return;
    last_print = p.elapsed_seconds;
    std::string part;
    if (p.parts > 1) part = "part " + std::to_string(p.part) + "/" + std::to_string(p.parts) + "  ";
    std::fprintf(
        stderr, "spheremap: %5.1f s  %s%-9s level %d/%d (%zu vertices)  iteration %zu  folds %zu\n",
        p.elapsed_seconds, part.c_str(), std::string(p.stage).c_str(), p.level, p.levels,
        p.vertices, p.iteration, p.folds);
  };
  return control;
}

MappedInput map_input(const Arguments& args, const PrepareOptions& prepare,
                      const MapOptions& options, const MapControl& control) {
  // --time-limit counts from here: reading and preparing a large file take seconds too.
  MapControl timed = control;
  if (!timed.clock_start) timed.clock_start = std::chrono::steady_clock::now();
  GltfReadStats stats;
  MappedInput out;
  out.input = read_mesh_file(args.positional()[0], gltf_options(args), &stats, &out.look);
  for (const std::string& warning : stats.warnings)
    std::fprintf(stderr, "spheremap: warning: %s\n", warning.c_str());
  out.input_warnings = stats.warnings;
  // Prepared once; the refusal carries what the glTF scene says (which meshes it draws,
  // which option maps one), which map_mesh alone could not know.
  const auto start = std::chrono::steady_clock::now();
  // The limit stops an envelope (it has no partial result to write), not the exact path.
  PrepareOptions timed_prepare = prepare;
  const double limit = options.time_limit_seconds;
  const auto clock_start = *timed.clock_start;
  // The preparation has no partial result to write either, but a limit that passes during
  // a short one still lets the map start and write what it reaches (its stages stop at
  // the limit): it is stopped once the limit has passed by as much again, or by a second,
  // whichever is longer. (An instanced scene of 1,899 teapots, 7.6M triangles, was
  // prepared for minutes under a 60 s limit.)
  const double prepare_limit = std::max(2 * limit, limit + 1);
  auto passed = [clock_start](double seconds) {
    return std::chrono::steady_clock::now() - clock_start >= std::chrono::duration<double>(seconds);
  };
  if (limit > 0) {
    timed_prepare.envelope_should_stop = [passed, limit] { return passed(limit); };
    timed_prepare.should_stop = [outer = prepare.should_stop, passed, prepare_limit] {
      return (outer && outer()) || passed(prepare_limit);
    };
  }
  // Envelopes are deferred and then built as the service's worker builds them
  // (build_envelopes), so the command runs the service's path and skips what only `info`
  // reports (the topology of an input that is wrapped whole).
  timed_prepare.defer_envelopes = true;
  PreparedMesh prepared;
  try {
    prepared = prepare_input(out.input, &out.look, timed_prepare);
    build_envelopes(prepared, out.input, &out.look, timed_prepare.envelope_should_stop);
  } catch (const InputError& e) {
    if (e.check() != "stopped" || limit <= 0) throw;
    char message[200];
    if (passed(prepare_limit))
      std::snprintf(message, sizeof message,
                    "the time limit (%g s) passed while the input was being prepared "
                    "(stopped at %g s); nothing was mapped",
                    limit, prepare_limit);
    else
      std::snprintf(message, sizeof message,
                    "the time limit (%g s) passed while an envelope was being built "
                    "(preparation); nothing was mapped",
                    limit);
    // A scene that draws one mesh many times (nodes or GPU instances) is as many parts;
    // the mesh alone is prepared and mapped once.
    std::string hint;
    if (stats.repeated_mesh >= 0)
      hint = "; the scene draws mesh " + std::to_string(stats.repeated_mesh) + " " +
             std::to_string(stats.repeated_mesh_draws) + " times: --mesh " +
             std::to_string(stats.repeated_mesh) + " maps it once";
    throw TimeLimitError(message + hint);
  }
  const double prepare_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  require_none(input_failures(prepared, &stats));
  // The limit covers the whole command, so the map stops early by what the stages after
  // it take: metrics, the float32 check and writing took 0.7-0.9 s on 1.3M triangles
  // (1e-6 s per triangle leaves a margin), at most half the limit.
  MapOptions limited = options;
  if (limited.time_limit_seconds > 0)
    limited.time_limit_seconds -=
        std::min(0.5 * limited.time_limit_seconds,
                 1e-6 * static_cast<double>(prepared.welded.mesh.face_count()));
  out.mapped = map_prepared(std::move(prepared), limited, timed);
  out.mapped.prepare_seconds = prepare_seconds;
  return out;
}

void print_parts_left_out(const PreparedMesh& prepared) {
  std::vector<const PartReport*> out;
  size_t faces = 0, faces_out = 0;
  for (const PartReport& part : prepared.parts) {
    faces += part.faces;
    if (part.mappable()) continue;
    out.push_back(&part);
    faces_out += part.faces;
  }
  if (out.empty()) return;
  std::stable_sort(out.begin(), out.end(),
                   [](const PartReport* a, const PartReport* b) { return a->faces > b->faces; });
  std::string line = counted(out.size(), "part") + " of " + std::to_string(prepared.parts.size()) +
                     " left out (" + std::to_string(faces_out) + " of " + std::to_string(faces) +
                     " faces; metrics.parts lists each):";
  for (size_t k = 0; k < out.size() && k < 3; ++k)
    line += std::string(k ? ";" : "") + " part " + std::to_string(out[k] - prepared.parts.data()) +
            " (" + counted(out[k]->faces, "face") + "): " + out[k]->failures.front().message;
  if (out.size() > 3) line += "; and " + std::to_string(out.size() - 3) + " more";
  std::fprintf(stderr, "spheremap: warning: %s\n", line.c_str());
}

std::string fix_hint(const Fix& fix) {
  if (fix.empty()) return "";
  std::string flag = "--" + fix.option;
  std::replace(flag.begin(), flag.end(), '_', '-');
  if (fix.value != "true") {
    flag += ' ';
    flag += fix.plain_value();
  }
  return flag + " " + fix.effect;
}

GltfReadOptions gltf_options(const Arguments& args) {
  GltfReadOptions options;
  const std::string mesh = args.text("mesh", "");
  if (!mesh.empty() && mesh.find_first_not_of("0123456789") == std::string::npos)
    options.mesh_index = static_cast<int>(args.integer("mesh", 0, 0, 1 << 30));
  else
    options.mesh_name = mesh;
  return options;
}

}  // namespace spheremap::cli
