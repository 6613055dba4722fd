#include "server/job.h"

namespace spheremap::server {

std::string_view to_string(JobStatus status) {
  switch (status) {
    case JobStatus::kQueued:
      return "queued";
    case JobStatus::kRunning:
      return "running";
    case JobStatus::kSucceeded:
      return "succeeded";
    case JobStatus::kFailed:
      return "failed";
    case JobStatus::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

std::optional<JobStatus> job_status_from(std::string_view text) {
  for (JobStatus s : {JobStatus::kQueued, JobStatus::kRunning, JobStatus::kSucceeded,
                      JobStatus::kFailed, JobStatus::kCancelled})
    if (to_string(s) == text) return s;
  return std::nullopt;
}

size_t Job::artifact_bytes() const {
  size_t total = 0;
  for (const Artifact& a : artifacts) total += a.bytes.size();
  return total;
}

}  // namespace spheremap::server
