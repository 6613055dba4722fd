// A job's handling on a server thread (the in-process workers, the Redis workers) must
// never end the process: an exception escaping a std::thread calls std::terminate, and
// every job in memory is lost with it (measured: a GLB whose 480 images named one
// bufferView made encode_request throw std::bad_alloc; the server exited with 134).
// run_guarded() turns what escapes into that one job's failure.
#pragma once

#include <functional>

#include "api/job.h"

namespace spheremap::server {

// Runs `run` and returns its status; std::bad_alloc fails the job as out_of_memory (507),
// any other exception as internal (500), with what it said.
api::JobStatus run_guarded(api::Job& job, const std::function<api::JobStatus()>& run);

}  // namespace spheremap::server
