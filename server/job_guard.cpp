#include "server/job_guard.h"

#include <new>

namespace spheremap::server {
namespace {

void fail(api::Job& job, int status, const char* problem, const char* title,
          const char* detail) noexcept {
  try {
    std::lock_guard lock(job.mutex);
    job.artifacts.clear();  // a partial answer is never served, and its memory is needed
    job.metrics = nullptr;
    job.error = api::JobError{status, problem, title, detail};
  } catch (...) {
    // Not even the error fits in memory: the job still ends as failed, without a detail.
  }
}

}  // namespace

api::JobStatus run_guarded(api::Job& job, const std::function<api::JobStatus()>& run) {
  try {
    return run();
  } catch (const std::bad_alloc&) {
    fail(job, 507, "out_of_memory", "Out of memory",
         "the server ran out of memory handling this job; the job failed, the server and the "
         "other jobs are unaffected; try a smaller mesh");
  } catch (const std::exception& e) {
    fail(job, 500, "internal", "Internal error", e.what());
  } catch (...) {
    fail(job, 500, "internal", "Internal error", "an unknown exception");
  }
  return api::JobStatus::kFailed;
}

}  // namespace spheremap::server
