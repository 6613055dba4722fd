#include "server/job_runner.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/input_error.h"

namespace spheremap::server {
namespace {

JobError map_failure(const MappedMesh& mapped, double time_limit) {
  const MapResult& map = mapped.map;
  std::ostringstream detail;
  if (map.stop_reason == StopReason::kTimeLimit) {
    detail << "the map stopped at the time limit of " << time_limit << " s with " << map.check.folds
           << " folded triangles left";
    return {422, "time_limit", "Time limit reached", detail.str()};
  }
  detail << "no bijective map reached (" << to_string(map.stop_reason) << "): " << map.check.folds
         << " folded triangles left after " << map.attempts << " attempts";
  return {422, "not_bijective", "No bijective map", detail.str()};
}

void make_artifacts(Job& job, const JobSpec& spec, const MappedMesh& mapped) {
  SphereAsset sphere =
      sphere_asset(spec.input, mapped, spec.map, spec.layout, spec.draco_position_bits);
  std::lock_guard lock(job.mutex);
  job.metrics = std::move(sphere.metrics);
  job.artifacts.push_back({"sphere.glb", "model/gltf-binary", std::move(sphere.glb)});
  job.artifacts.push_back({"metrics.json", "application/json", job.metrics.dump(2) + "\n"});
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
  MapControl control;
  control.cancel = &job.cancel;
  control.on_progress = [&job](const MapProgress& p) {
    std::lock_guard lock(job.mutex);
    job.progress = {std::string(p.stage), p.level, p.levels, p.vertices, p.iteration, p.folds};
  };
  try {
    const MappedMesh mapped = map_prepared(std::move(spec->prepared), options, control);
    if (job.cancel || mapped.map.stop_reason == StopReason::kCancelled)
      return JobStatus::kCancelled;
    if (!mapped.map.check.bijective) {
      std::lock_guard lock(job.mutex);
      job.error = map_failure(mapped, options.time_limit_seconds);
      return JobStatus::kFailed;
    }
    {
      std::lock_guard lock(job.mutex);
      job.progress.stage = "writing";
    }
    make_artifacts(job, *spec, mapped);
    return job.cancel ? JobStatus::kCancelled : JobStatus::kSucceeded;
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
