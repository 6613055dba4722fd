// The service as a process: binds the port (a worker node: only the health port), serves the API
// until SIGTERM or SIGINT, then drains (readyz fails, new jobs get 503, queued and running jobs get
// the grace period, what is left is cancelled) and returns 0. Logs the effective configuration at
// start.
#pragma once

#include "server/config.h"

namespace spheremap::server {

// What this process is: the HTTP API (and workers, unless `workers` is 0), or a worker
// node of a Redis queue with no public HTTP (only the health port, when configured).
enum class Role { kApi, kWorker };

// Returns the process exit code: 0 after a graceful stop, 1 when a port cannot be bound
// or the configuration cannot run (logged).
int serve(const ServerConfig& config, Role role = Role::kApi);

}  // namespace spheremap::server
