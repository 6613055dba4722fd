// GET /v1/jobs/{id}/events: a job's progress as Server-Sent Events, for browsers
// (EventSource) and anything else that would rather listen than poll.
//
// Events: `progress` (data: the job's progress object, sent when it changes, checked
// every 250 ms), then one `status` (data: the whole job, as GET /v1/jobs/{id} answers it)
// when the job ends, and the stream closes. A comment line every 15 s keeps proxies from
// closing an idle stream. Each stream holds an HTTP thread while it lasts, so at most a
// quarter of them stream at once, and half of those for one tenant (event_stream_slots.h);
// beyond that the answer is 503 with Retry-After and the client polls instead.
#pragma once

#include <httplib.h>

#include <memory>
#include <string>

#include "api/backend.h"
#include "api/event_stream_slots.h"

namespace spheremap::api {

// `tenant`: the requester's (its API key's tenant, or its address).
void stream_job_events(Backend& service, const std::shared_ptr<Job>& job, const std::string& tenant,
                       httplib::Response& response, const std::shared_ptr<EventStreamSlots>& slots);

}  // namespace spheremap::api
