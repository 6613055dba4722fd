// Runs one job on the calling worker thread: maps the prepared mesh with the job's
// options (cancellable, time-limited, reporting progress into the job), then makes the
// artifacts it asked for. Returns the terminal status; the job holds the results or the
// error. Never throws.
#pragma once

#include "server/api_types.h"

namespace spheremap::server {

struct RunLimits {
  double time_limit_seconds = 300;
  int threads = 1;
};

JobStatus run_job(Job& job, const RunLimits& limits);

}  // namespace spheremap::server
