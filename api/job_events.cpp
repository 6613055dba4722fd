#include "api/job_events.h"

#include "api/job_view.h"
#include "api/problem.h"

namespace spheremap::api {
namespace {

using namespace std::chrono_literals;

std::string event(const char* name, const nlohmann::json& data) {
  return std::string("event: ") + name +
         "\ndata: " + data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n\n";
}

struct Stream {
  std::shared_ptr<Job> job;
  std::unique_ptr<EventStreamSlots::Slot> slot;  // given back when the stream ends
  std::string last_progress;
  Clock::time_point last_write = Clock::now();
};

}  // namespace

void stream_job_events(Backend& service, const std::shared_ptr<Job>& job, const std::string& tenant,
                       httplib::Response& response,
                       const std::shared_ptr<EventStreamSlots>& slots) {
  const int max_streams = std::max(1, service.settings().http_threads / 4);
  EventStreamSlots::Refusal refusal;
  auto slot = EventStreamSlots::acquire(slots, tenant, max_streams, refusal);
  if (refusal == EventStreamSlots::Refusal::kServerFull)
    throw Problem(503, "too_many_streams", "Too many event streams",
                  "at most " + std::to_string(max_streams) +
                      " event streams at once; poll GET /v1/jobs/{id} instead");
  if (refusal == EventStreamSlots::Refusal::kTenantFull)
    throw Problem(503, "too_many_streams", "Too many event streams",
                  "at most " + std::to_string(EventStreamSlots::per_tenant(max_streams)) +
                      " event streams at once per client (of " + std::to_string(max_streams) +
                      " for the server); poll GET /v1/jobs/{id} instead");
  auto stream = std::make_shared<Stream>();
  stream->job = job;
  stream->slot = std::move(slot);
  response.set_header("Cache-Control", "no-cache");
  response.set_header("X-Accel-Buffering", "no");  // nginx: pass events through at once
  response.set_chunked_content_provider(
      "text/event-stream",
      [stream, &service](size_t, httplib::DataSink& sink) {
        // The job as it stands after up to 250 ms (a Redis queue: a fresh snapshot).
        try {
          stream->job = service.queue().wait(stream->job, 0.25);
        } catch (const QueueUnavailable&) {
          // Redis away for a moment: keep the stream, say nothing new this tick.
        }
        Job& job = *stream->job;
        bool terminal;
        {
          std::lock_guard lock(job.mutex);
          terminal = is_terminal(job.status);
        }
        nlohmann::json view;
        try {
          view = job_json(job, service.queue().queue_position(job));
        } catch (const QueueUnavailable&) {
          view = job_json(job, 0);
        }
        std::string out;
        const std::string progress = view["progress"].dump();
        if (progress != stream->last_progress) {
          nlohmann::json data = view["progress"];
          data["status"] = view["status"];
          out += event("progress", data);
          stream->last_progress = progress;
        }
        if (terminal) out += event("status", view);
        if (out.empty() && Clock::now() - stream->last_write > 15s) out = ": keep-alive\n\n";
        if (!out.empty()) {
          if (!sink.write(out.data(), out.size())) return false;  // the client went away
          stream->last_write = Clock::now();
        }
        if (terminal) sink.done();
        return true;
      },
      [stream](bool) { stream->slot.reset(); });
}

}  // namespace spheremap::api
