// The server builds on the API layer (core <- api <- server): the job model, the queue
// interface, logging and metrics it shares with the routes are api/'s, used here
// unqualified.
#pragma once

#include "api/backend.h"
#include "api/job.h"
#include "api/job_queue.h"
#include "api/log.h"

namespace spheremap::server {
using namespace spheremap::api;
}  // namespace spheremap::server
