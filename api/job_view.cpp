#include "api/job_view.h"

#include <ctime>

#include "api/problem.h"

namespace spheremap::api {
namespace {

std::string iso_time(std::chrono::system_clock::time_point t) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(t);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

double seconds(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

}  // namespace

std::string job_path(const std::string& id) {
  return "/v1/jobs/" + id;
}

nlohmann::json job_json(const Job& job, size_t queue_position) {
  std::lock_guard lock(job.mutex);
  const auto now = Clock::now();
  const Clock::time_point end = job.finished.value_or(now);
  nlohmann::json out = {
      {"id", job.id},
      {"status", to_string(job.status)},
      {"created_at", iso_time(job.created_wall)},
      {"input",
       {{"format", job.input_format},
        {"bytes", job.input_bytes},
        {"vertices", job.input_vertices},
        {"faces", job.input_faces}}},
      {"options", job.options},
      {"progress",
       {{"stage", job.progress.stage},
        {"level", job.progress.level},
        {"levels", job.progress.levels},
        {"vertices", job.progress.vertices},
        {"iteration", job.progress.iteration},
        {"folds", job.progress.folds},
        {"energy", job.progress.energy},
        {"part", job.progress.part},
        {"parts", job.progress.parts},
        {"elapsed_seconds", job.started ? seconds(*job.started, end) : 0.0}}},
      {"links", {{"self", job_path(job.id)}}},
  };
  if (job.status == JobStatus::kQueued) out["queue_position"] = queue_position;
  if (job.started) out["waited_seconds"] = seconds(job.created, *job.started);
  if (!job.metrics.is_null()) out["metrics"] = job.metrics;
  if (!job.artifacts.empty()) {
    nlohmann::json artifacts = nlohmann::json::object();
    for (const Artifact& a : job.artifacts)
      artifacts[a.name] = {{"href", job_path(job.id) + "/artifacts/" + a.name},
                           {"type", a.content_type},
                           {"bytes", a.size}};  // a listing (Redis) has no bytes
    out["artifacts"] = artifacts;
  }
  if (job.error)
    out["error"] = problem_json(
        Problem(job.error->status, job.error->problem, job.error->title, job.error->detail),
        job_path(job.id));
  if (!job.cancel_reason.empty()) out["cancel_reason"] = job.cancel_reason;
  return out;
}

}  // namespace spheremap::api
