// The service as a process: binds the port, serves the API until SIGTERM or SIGINT, then
// drains (readyz fails, new jobs get 503, queued and running jobs get the grace period,
// what is left is cancelled) and returns 0. Logs the effective configuration at start.
#pragma once

#include "server/config.h"

namespace spheremap::server {

// Returns the process exit code: 0 after a graceful stop, 1 when the port cannot be bound.
int serve(const ServerConfig& config);

}  // namespace spheremap::server
