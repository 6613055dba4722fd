#include "api/job.h"

#include <sys/random.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "api/job_queue.h"

namespace spheremap::api {

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

SharedBytes share_bytes(std::string bytes) {
  return std::make_shared<const std::string>(std::move(bytes));
}

Artifact make_artifact(std::string name, std::string content_type, std::string bytes) {
  const size_t size = bytes.size();
  return {std::move(name), std::move(content_type), share_bytes(std::move(bytes)), size};
}

size_t Job::artifact_bytes() const {
  size_t total = 0;
  for (const Artifact& a : artifacts) total += a.size;
  for (const auto& [name, view] : gltf_views) total += view->size();
  return total;
}

// 128 bits from the kernel's CSPRNG (getrandom): ids are the only handle on a job, so
// they must not be predictable (a std::mt19937_64 stream is rebuilt from 156 outputs).
std::string new_job_id() {
  uint64_t words[2];
  size_t got = 0;
  while (got < sizeof words) {
    const ssize_t n = getrandom(reinterpret_cast<char*>(words) + got, sizeof words - got, 0);
    if (n > 0)
      got += static_cast<size_t>(n);
    else if (errno != EINTR)
      throw std::runtime_error("getrandom failed: " + std::string(std::strerror(errno)));
  }
  char text[33];
  std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(words[0]),
                static_cast<unsigned long long>(words[1]));
  return text;
}

}  // namespace spheremap::api
