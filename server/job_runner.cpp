#include "server/job_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>

#include "core/map/certification.h"
#include "core/mesh/input_error.h"
#include "core/outputs/map_outputs.h"
#include "core/prepare/prepare_mesh.h"

namespace spheremap::server {
namespace {

void add_artifact(Job& job, std::string name, std::string type, std::string bytes) {
  std::lock_guard lock(job.mutex);
  job.artifacts.push_back(make_artifact(std::move(name), std::move(type), std::move(bytes)));
}

void set_stage(Job& job, const char* stage) {
  std::lock_guard lock(job.mutex);
  job.progress.stage = stage;
}

// When the job's assets must stop: it was cancelled, or its time limit (counted from
// the start of the run, like the map's) passed. Core's long loops ask `should_stop`.
struct AssetDeadline {
  AssetDeadline(const std::atomic<bool>& cancel, double limit_seconds)
      : limit_seconds(limit_seconds),
        deadline(limit_seconds > 0
                     ? Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(limit_seconds))
                     : Clock::time_point::max()),
        should_stop([&cancel, at = deadline] { return cancel || Clock::now() >= at; }) {}
  bool passed() const { return Clock::now() >= deadline; }

  double limit_seconds;
  Clock::time_point deadline;
  std::function<bool()> should_stop;
};

// Runs `make` for the asset `name` when it was asked for; an asset that cannot be
// written (float32_range: positions past float32's range, in a glTF placed by a huge
// node scale) is left out and its problem kept, so the map and the other assets stay
// downloadable and the job still fails with that problem. An asset the time limit
// stops (or finds passed) is left out the same way, as "time_limit".
template <typename Make>
void add_asset(Job& job, const char* name, nlohmann::json& metrics,
               std::optional<JobError>& asset_error, const AssetDeadline& time, Make make) {
  if (job.cancel) return;
  auto fail = [&](const std::string& check, const std::string& detail) {
    metrics[name] = {{"error", {{"check", check}, {"detail", detail}}}};
    if (!asset_error)
      asset_error =
          check == "time_limit"
              ? JobError{422, check, "Time limit reached", std::string(name) + ": " + detail}
              : JobError{422, check, "Asset cannot be written", std::string(name) + ": " + detail};
  };
  std::ostringstream limit;
  limit << "the job's time limit (" << time.limit_seconds << " s) passed before it was written";
  if (time.passed()) return fail("time_limit", limit.str());
  set_stage(job, name);
  try {
    make();
  } catch (const InputError& e) {
    if (e.check() == "stopped" && job.cancel) return;  // the job ends as cancelled
    if (e.check() == "stopped") return fail("time_limit", limit.str());
    fail(e.check(), e.what());
  }
}

// The sphere, then (for a certified map) each asset asked for, checking for cancellation
// between them, then metrics.json with everything measured. Returns the verdict on the
// sphere as written: a map that is not certified keeps only sphere.glb and metrics.json,
// marked "bijective": false, so the best map reached can still be downloaded.
Certification make_artifacts(Job& job, const JobSpec& spec, const MappedMesh& mapped, int threads,
                             const AssetDeadline& time, std::optional<JobError>& asset_error) {
  SphereAsset sphere =
      sphere_asset(spec.input, mapped, spec.map, spec.layout, spec.draco_position_bits, &spec.look);
  const Certification verdict = certify(mapped, sphere.written);
  nlohmann::json metrics = std::move(sphere.metrics);
  if (!spec.input_warnings.empty()) metrics["input_warnings"] = spec.input_warnings;
  add_artifact(job, "sphere.glb", "model/gltf-binary", std::move(sphere.glb));
  auto wanted = [&](const char* name) {
    return verdict.certified &&
           std::find(spec.outputs.begin(), spec.outputs.end(), name) != spec.outputs.end();
  };
  if (wanted("remesh"))
    add_asset(job, "remesh", metrics, asset_error, time, [&] {
      RemeshAsset remesh = remesh_asset(mapped, spec.remesh_resolution, threads, &spec.input,
                                        &spec.look, &time.should_stop, spec.normal_map);
      metrics["remesh"] = std::move(remesh.metrics);
      add_artifact(job, "remesh.glb", "model/gltf-binary", std::move(remesh.glb));
      add_artifact(job, "geometry_image.png", "image/png", std::move(remesh.geometry_image_png));
    });
  if (wanted("uv"))
    add_asset(job, "uv", metrics, asset_error, time, [&] {
      UvAsset uv = uv_asset(mapped, &spec.input, &spec.look);
      metrics["uv"] = std::move(uv.metrics);
      add_artifact(job, "uv.glb", "model/gltf-binary", std::move(uv.glb));
    });
  if (wanted("morph"))
    add_asset(job, "morph", metrics, asset_error, time, [&] {
      MorphAsset morph = morph_asset(mapped, 4, &spec.input, &spec.look);
      metrics["morph"] = std::move(morph.metrics);
      add_artifact(job, "morph.glb", "model/gltf-binary", std::move(morph.glb));
    });
  add_artifact(job, "metrics.json", "application/json", metrics.dump(2) + "\n");
  std::lock_guard lock(job.mutex);
  job.metrics = std::move(metrics);
  return verdict;
}

// The envelopes the intake left (PreparedMesh::pending), built first, under the job's
// time limit and cancel: here, in the worker, the job's memory charge covers them
// (estimated_job_bytes). False, with the job's error set, when none could be made or the
// time limit stopped it; a cancel is left to the caller.
bool build_pending_envelopes(Job& job, JobSpec& spec, const AssetDeadline& time) {
  set_stage(job, "envelope");
  try {
    build_envelopes(spec.prepared, spec.input, &spec.look, time.should_stop);
    return true;
  } catch (const InputError& e) {
    if (e.check() == "stopped" && job.cancel) return false;
    std::lock_guard lock(job.mutex);
    if (e.check() == "stopped") {
      std::ostringstream detail;
      detail << "the envelope was not built within the job's time limit (" << time.limit_seconds
             << " s); ask for a smaller wrap_resolution or a longer time_limit_seconds";
      job.error = JobError{422, "time_limit", "Time limit reached", detail.str()};
    } else {
      job.error = JobError{422, e.check(), "Envelope cannot be made", e.what()};
    }
    return false;
  }
}

}  // namespace

JobStatus run_job(Job& job, const RunLimits& limits) {
  JobSpec* spec;
  {
    std::lock_guard lock(job.mutex);
    spec = job.spec.get();
  }
  MapOptions options = spec->map;
  options.smoothing.threads = limits.threads;
  options.time_limit_seconds = options.time_limit_seconds > 0
                                   ? std::min(options.time_limit_seconds, limits.time_limit_seconds)
                                   : limits.time_limit_seconds;
  const Clock::time_point started = Clock::now();
  const AssetDeadline time(job.cancel, options.time_limit_seconds);
  MapControl control;
  control.cancel = &job.cancel;
  control.on_progress = [&job](const MapProgress& p) {
    std::lock_guard lock(job.mutex);
    job.progress = {std::string(p.stage),
                    p.level,
                    p.levels,
                    p.vertices,
                    p.iteration,
                    p.folds,
                    p.energy,
                    p.part,
                    p.parts};
  };
  try {
    if (spec->prepared.pending.any()) {
      if (!build_pending_envelopes(job, *spec, time))
        return job.cancel ? JobStatus::kCancelled : JobStatus::kFailed;
      // The map gets what the envelope left of the job's time limit.
      const double spent = std::chrono::duration<double>(Clock::now() - started).count();
      if (options.time_limit_seconds > 0)
        options.time_limit_seconds = std::max(options.time_limit_seconds - spent, 0.01);
    }
    const MappedMesh mapped = map_prepared(std::move(spec->prepared), options, control);
    if (job.cancel || mapped.map.stop_reason == StopReason::kCancelled)
      return JobStatus::kCancelled;
    {
      std::lock_guard lock(job.mutex);
      job.progress.stage = "writing";
    }
    std::optional<JobError> asset_error;
    const Certification verdict =
        make_artifacts(job, *spec, mapped, limits.threads, time, asset_error);
    if (job.cancel) return JobStatus::kCancelled;
    if (!verdict.certified) {
      std::lock_guard lock(job.mutex);
      std::ostringstream limit;
      limit << " (limit " << time.limit_seconds << " s)";
      job.error =
          verdict.problem == "time_limit"
              ? JobError{422, "time_limit", "Time limit reached", verdict.detail + limit.str()}
              : JobError{422, "not_bijective", "No bijective map", verdict.detail};
      return JobStatus::kFailed;
    }
    if (asset_error) {
      std::lock_guard lock(job.mutex);
      job.error = std::move(asset_error);
      return JobStatus::kFailed;
    }
    return JobStatus::kSucceeded;
  } catch (const InputError& e) {
    std::lock_guard lock(job.mutex);
    job.error = JobError{422, e.check(), "Mesh cannot be mapped", e.what()};
  } catch (const std::bad_alloc&) {
    std::lock_guard lock(job.mutex);
    job.error = JobError{507, "out_of_memory", "Out of memory",
                         "the job ran out of memory; try a smaller mesh"};
  } catch (const std::exception& e) {
    std::lock_guard lock(job.mutex);
    job.error = JobError{500, "internal", "Internal error", e.what()};
  }
  return JobStatus::kFailed;
}

}  // namespace spheremap::server
