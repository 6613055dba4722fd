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

size_t Job::artifact_bytes() const {
  size_t total = 0;
  for (const Artifact& a : artifacts) total += a.bytes.size();
  return total;
}

}  // namespace spheremap::server
