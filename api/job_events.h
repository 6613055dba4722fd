// GET /v1/jobs/{id}/events: a job's progress as Server-Sent Events, for browsers
// (EventSource) and anything else that would rather listen than poll.
//
// Events: `progress` (data: the job's progress object, sent when it changes, checked
// every 250 ms), then one `status` (data: the whole job, as GET /v1/jobs/{id} answers it)
// when the job ends, and the stream closes. A comment line every 15 s keeps proxies from
// closing an idle stream. Each stream holds an HTTP thread while it lasts, so at most a
// quarter of them stream at once; beyond that the answer is 503 with Retry-After and the
// client polls instead.
#pragma once

#include <httplib.h>

#include <atomic>
#include <memory>

#include "api/backend.h"

namespace spheremap::api {

void stream_job_events(Backend& service, const std::shared_ptr<Job>& job,
                       httplib::Response& response, std::shared_ptr<std::atomic<int>> streams);

}  // namespace spheremap::api
