#include "api/routes.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <new>

#include "api/client_address.h"
#include "api/idempotency_key.h"
#include "api/job_events.h"
#include "api/job_request.h"
#include "api/job_view.h"
#include "api/log.h"
#include "api/problem.h"
#include "api/shared_body.h"
#include "web/web_assets.h"

namespace spheremap::api {
namespace {

const char* const kJobId = "([0-9a-f]{32})";

// The body's length; a shared body (send_shared) is not in response.body, its length is
// in the header cpp-httplib wrote.
size_t bytes_out(const httplib::Response& response) {
  size_t bytes = response.body.size();
  if (bytes == 0) {
    const std::string length = response.get_header_value("Content-Length");
    std::from_chars(length.data(), length.data() + length.size(), bytes);
  }
  return bytes;
}

void send_json(httplib::Response& response, int status, const nlohmann::json& body) {
  response.status = status;
  response.set_content(body.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n",
                       "application/json");
}

// Whose request this is: the API key's tenant (the pre-routing handler has already
// refused requests without a valid key when keys are configured), else the client's
// address, which quotas and fair scheduling then apply to.
std::string tenant_of(const Backend& service, const httplib::Request& request) {
  if (service.api_keys().enabled())
    return "key:" +
           service.api_keys().tenant_for(request.get_header_value("Authorization")).value_or("");
  return "address:" + client_address(service.settings(), request);
}

// The job of the path's first capture, or a 404 / 410 problem. With API keys another
// tenant's job does not exist, as far as this request can tell.
std::shared_ptr<Job> find_job(Backend& service, const httplib::Request& request) {
  const std::string id = request.matches[1];
  JobQueue::Lookup found = service.queue().find(id);
  if (found.job && service.api_keys().enabled() && found.job->tenant != tenant_of(service, request))
    throw Problem(404, "job_not_found", "No such job", "no job with id " + id);
  if (found.job) return found.job;
  if (found.evicted)
    throw Problem(410, "gone", "Job results expired",
                  "job " + id + " finished and its results were dropped (result_ttl_seconds " +
                      "or result_memory_bytes reached)");
  throw Problem(404, "job_not_found", "No such job", "no job with id " + id);
}

Problem out_of_memory_problem() {
  return Problem(503, "out_of_memory", "Out of memory",
                 "the server ran out of memory handling this request; nothing was kept; retry "
                 "later or send a smaller mesh");
}

// Reads, checks and queues a submission; throws Problems for every refusal. `replayed`:
// the request's Idempotency-Key named a job of this tenant already kept, returned as is.
std::shared_ptr<Job> submit(Backend& service, const httplib::Request& request, bool& replayed) {
  const std::string key = idempotency_key_of(request);  // 400 before anything else
  if (service.draining()) {
    service.metrics().rejected("shutting_down");
    throw Problem(503, "shutting_down", "Shutting down",
                  "the server is shutting down and accepts no new jobs");
  }
  if (!service.ready()) {
    service.metrics().rejected("queue_unavailable");
    throw QueueUnavailable("readiness check failed");
  }
  const std::string tenant = tenant_of(service, request);
  // A retry of a submission already queued is answered before its body is read, and a
  // full queue does not refuse it.
  if (!key.empty()) {
    if (std::shared_ptr<Job> earlier = service.queue().replay(tenant, key)) {
      replayed = true;
      return earlier;
    }
  }
  if (service.queue().queued() >= service.settings().queue_capacity) {
    service.metrics().rejected("queue_full");
    throw Problem(429, "queue_full", "Queue full",
                  "the job queue is full (" + std::to_string(service.settings().queue_capacity) +
                      " jobs waiting); retry later");
  }
  std::unique_ptr<JobSpec> spec;
  try {
    service.intake().run([&](const IntakeDeadline& deadline) {
      spec = read_job_request(request, service.settings(), deadline);
    });
  } catch (const Problem& p) {
    service.metrics().rejected(p.extra.value("check", p.slug));
    throw;
  } catch (const std::bad_alloc&) {
    // What was allocated for this mesh is freed by now: the server goes on.
    service.metrics().rejected("out_of_memory");
    throw out_of_memory_problem();
  }
  spec->tenant = tenant;
  spec->idempotency_key = key;
  std::shared_ptr<Job> job;
  switch (service.queue().submit(std::move(spec), job)) {
    case JobQueue::Admission::kAccepted:
      return job;
    case JobQueue::Admission::kReplayed:
      replayed = true;
      return job;
    case JobQueue::Admission::kQueueFull:
      service.metrics().rejected("queue_full");
      throw Problem(429, "queue_full", "Queue full", "the job queue is full; retry later");
    case JobQueue::Admission::kTenantQueueFull:
      service.metrics().rejected("tenant_quota");
      throw Problem(429, "tenant_quota", "Too many queued jobs",
                    "you have " + std::to_string(service.settings().tenant_max_queued) +
                        " jobs waiting (tenant_max_queued); retry when one has started");
    case JobQueue::Admission::kShuttingDown:
      service.metrics().rejected("shutting_down");
      throw Problem(503, "shutting_down", "Shutting down",
                    "the server is shutting down and accepts no new jobs");
    case JobQueue::Admission::kTooLarge:
      service.metrics().rejected("queue_entry_too_large");
      throw Problem(413, "queue_entry_too_large", "Job too large for the queue",
                    "the prepared job is larger than the shared queue (Redis) stores in one "
                    "value (proto-max-bulk-len); nothing was stored; send a smaller mesh");
    case JobQueue::Admission::kStorageFull:
      service.metrics().rejected("queue_storage_full");
      throw Problem(507, "queue_storage_full", "Job queue out of memory",
                    "the shared queue (Redis) is out of memory (maxmemory) and refused the "
                    "job; nothing was stored; retrying helps only once results have expired "
                    "or the operator has given Redis more memory");
  }
  return job;
}

// A replayed submission says so (as Stripe's API does): the job is the one the key made.
void mark_replayed(httplib::Response& response, bool replayed) {
  if (replayed) response.set_header("Idempotent-Replayed", "true");
}

void post_job(Backend& service, const httplib::Request& request, httplib::Response& response) {
  bool replayed = false;
  const std::shared_ptr<Job> job = submit(service, request, replayed);
  mark_replayed(response, replayed);
  response.set_header("Location", job_path(job->id));
  response.set_header("Spheremap-Job", job->id);
  send_json(response, 202, job_json(*job, service.queue().queue_position(*job)));
}

// Prefer: wait=N (RFC 7240) shortens or lengthens the wait, within the configured one.
double sync_wait_seconds(const httplib::Request& request, double configured) {
  const std::string prefer = request.get_header_value("Prefer");
  const size_t at = prefer.find("wait=");
  if (at == std::string::npos) return configured;
  double wait = configured;
  const char* begin = prefer.data() + at + 5;
  std::from_chars(begin, prefer.data() + prefer.size(), wait);
  if (!std::isfinite(wait)) return configured;  // "wait=nan", "wait=inf"
  return std::clamp(wait, 0.0, configured);
}

void post_map(Backend& service, std::atomic<int>& waiting, const httplib::Request& request,
              httplib::Response& response) {
  bool replayed = false;
  const std::shared_ptr<Job> job = submit(service, request, replayed);
  mark_replayed(response, replayed);
  response.set_header("Spheremap-Job", job->id);
  // Waiting holds an HTTP thread: at most half of them may wait, so the rest can serve.
  const int max_waiting = std::max(1, service.settings().http_threads / 2);
  const double wait = sync_wait_seconds(request, service.settings().sync_timeout_seconds);
  std::shared_ptr<Job> now = job;
  if (waiting.fetch_add(1) < max_waiting) {
    try {
      now = service.queue().wait(job, wait);
    } catch (...) {
      waiting.fetch_sub(1);
      throw;
    }
  }
  waiting.fetch_sub(1);
  JobStatus status;
  {
    std::lock_guard lock(now->mutex);
    status = now->status;
  }
  if (!is_terminal(status)) {
    response.set_header("Location", job_path(job->id));
    send_json(response, 202, job_json(*now, service.queue().queue_position(*now)));
    return;
  }
  if (status == JobStatus::kSucceeded) {
    const std::optional<Artifact> sphere = service.queue().artifact(*now, "sphere.glb");
    if (!sphere)
      throw Problem(410, "gone", "Job results expired",
                    "job " + job->id + " finished and its results were dropped");
    std::lock_guard lock(now->mutex);
    response.set_header("Content-Location", job_path(job->id) + "/artifacts/sphere.glb");
    response.set_header("Link",
                        "<" + job_path(job->id) + "/artifacts/metrics.json>; rel=\"describedby\"");
    response.set_header("Spheremap-Bijective",
                        now->metrics.value("bijective_as_written", false) ? "true" : "false");
    response.set_header("Spheremap-Folds",
                        std::to_string(now->metrics.value("folds_as_written", size_t{0})));
    send_shared(response, sphere->bytes, sphere->content_type);
    response.status = 200;
    return;
  }
  std::lock_guard lock(now->mutex);
  const JobError error = now->error.value_or(
      JobError{503, "cancelled", "Job cancelled",
               now->cancel_reason.empty() ? "the job was cancelled" : now->cancel_reason});
  throw Problem(error.status, error.problem, error.title, error.detail, {{"job", job->id}});
}

void get_artifact(Backend& service, const httplib::Request& request, httplib::Response& response) {
  const std::shared_ptr<Job> job = find_job(service, request);
  const std::string name = request.matches[2];
  // Every .glb artifact is also served as .gltf (JSON, the buffer embedded as base64).
  const bool as_gltf = name.ends_with(".gltf");
  const std::string stored = as_gltf ? name.substr(0, name.size() - 5) + ".glb" : name;
  // The view is built on its first request and kept: every request shares its bytes.
  if (as_gltf) {
    if (SharedBytes view = service.queue().gltf_view(*job, stored)) {
      send_shared(response, std::move(view), "model/gltf+json");
      response.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
      return;
    }
  } else if (const std::optional<Artifact> a = service.queue().artifact(*job, stored)) {
    send_shared(response, a->bytes, a->content_type);
    if (name.ends_with(".glb"))
      response.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
    return;
  }
  std::lock_guard lock(job->mutex);
  if (!is_terminal(job->status))
    throw Problem(409, "not_ready", "Job not finished",
                  "job " + job->id + " is " + std::string(to_string(job->status)) +
                      "; artifacts exist once it has succeeded");
  throw Problem(404, "artifact_not_found", "No such artifact",
                "job " + job->id + " has no artifact '" + name + "'");
}

void delete_job(Backend& service, const httplib::Request& request, httplib::Response& response) {
  const std::shared_ptr<Job> job = find_job(service, request);
  if (service.queue().cancel(job, "cancelled by the client")) {
    JobStatus status;
    {
      std::lock_guard lock(job->mutex);
      status = job->status;
    }
    // A queued job is cancelled now; a running one stops within a fraction of a second.
    send_json(response, status == JobStatus::kCancelled ? 200 : 202, job_json(*job, 0));
    return;
  }
  service.queue().remove(job->id);
  response.status = 204;
}

std::string status_title(int status) {
  switch (status) {
    case 400:
      return "Bad request";
    case 404:
      return "Not found";
    case 405:
      return "Method not allowed";
    case 413:
      return "Request too large";
    case 414:
      return "URI too long";
    case 415:
      return "Unsupported media type";
    case 416:
      return "Range not satisfiable";
    default:
      return "HTTP " + std::to_string(status);
  }
}

// Wraps a handler: Problems become problem+json responses.
template <typename Body>
httplib::Server::Handler guarded(Body body) {
  return [body](const httplib::Request& request, httplib::Response& response) {
    try {
      body(request, response);
    } catch (const Problem& problem) {
      if (problem.status == 429) response.set_header("Retry-After", "5");
      if (problem.status == 503) response.set_header("Retry-After", "30");
      send_problem(response, problem, request.path);
    } catch (const AdmissionUnsettled& e) {
      // Redis went silent after the job was sent and stayed so: it may be stored.
      log_event({{"event", "queue_unavailable"}, {"error", e.what()}, {"job", e.job_id}});
      response.set_header("Retry-After", "5");
      send_problem(response,
                   Problem(503, "admission_unsettled", "Job admission unsettled",
                           "the shared job queue stopped answering after the job was sent; it "
                           "may have been stored as job " +
                               e.job_id + ": GET " + job_path(e.job_id) +
                               " before sending it again, or send it again with the same "
                               "Idempotency-Key",
                           {{"job", e.job_id}}),
                   request.path);
    } catch (const QueueUnavailable& e) {
      // Redis out of reach: nothing was accepted or changed (a submission whose answer was
      // lost was checked, or made void, before this); the client may retry soon.
      log_event({{"event", "queue_unavailable"}, {"error", e.what()}});
      response.set_header("Retry-After", "5");
      send_problem(response,
                   Problem(503, "queue_unavailable", "Job queue unavailable",
                           "the shared job queue cannot be reached; retry in a few seconds"),
                   request.path);
    }
  };
}

// The methods a known path answers, for 405 + Allow ("" for a path we do not serve).
// Plain string tests: std::regex trips GCC 12's maybe-uninitialized warning under ASan.
std::string allowed_methods(const std::string& path) {
  if (path == "/v1/jobs" || path == "/v1/map") return "POST, OPTIONS";
  if (path == "/" || path == "/healthz" || path == "/readyz" || path == "/metrics" ||
      path == "/v1/openapi.yaml" || (path.starts_with("/web/") && path.size() > 5) ||
      (path.starts_with("/examples/") && path.size() > 10))
    return "GET, OPTIONS";
  constexpr std::string_view kJobs = "/v1/jobs/";
  if (!path.starts_with(kJobs)) return "";
  std::string_view rest = std::string_view(path).substr(kJobs.size());
  const std::string_view id = rest.substr(0, 32);
  if (id.size() != 32 || id.find_first_not_of("0123456789abcdef") != std::string_view::npos)
    return "";
  rest.remove_prefix(32);
  if (rest.empty()) return "GET, DELETE, OPTIONS";
  if (rest == "/events" || (rest.starts_with("/artifacts/") && rest.size() > 11))
    return "GET, OPTIONS";
  return "";
}

// CORS: browsers on other origins may call the API when `cors_origins` allows them ("*",
// or a comma-separated list of origins echoed back one at a time); by default ("") none.
void add_cors_headers(const std::string& allowed, const httplib::Request& request,
                      httplib::Response& response) {
  if (allowed.empty()) return;
  const std::string origin = request.get_header_value("Origin");
  if (allowed == "*") {
    response.set_header("Access-Control-Allow-Origin", "*");
  } else if (!origin.empty() &&
             ("," + allowed + ",").find("," + origin + ",") != std::string::npos) {
    response.set_header("Access-Control-Allow-Origin", origin);
    response.set_header("Vary", "Origin");
  } else {
    return;
  }
  response.set_header("Access-Control-Expose-Headers",
                      "Location, Content-Location, Link, Retry-After, Spheremap-Job, "
                      "Spheremap-Bijective, Spheremap-Folds, Idempotent-Replayed");
}

// The page's policy: everything from our own origin (three.js is bundled), its one inline
// script (the import map) by hash, WebAssembly for the Draco and meshopt decoders, their
// workers and the user's chosen files as blob: URLs, embedded glTF buffers as data:.
// Never framed (clickjacking of the page that holds an API key).
std::string page_security_policy() {
  return "default-src 'self'; script-src 'self' 'wasm-unsafe-eval' 'sha256-" +
         std::string(web::import_map_sha256()) +
         "'; worker-src 'self' blob:; connect-src 'self' blob: data:; "
         "img-src 'self' blob: data:; style-src 'self'; object-src 'none'; base-uri 'none'; "
         "form-action 'self'; frame-ancestors 'none'";
}

void serve_asset(const httplib::Request& request, httplib::Response& response) {
  const web::Asset* asset = web::find_asset(request.path);
  if (!asset)
    throw Problem(404, "not_found", "Not found", "no page at " + request.path.substr(0, 200));
  std::string type(asset->content_type);
  if (type.starts_with("text/")) type += "; charset=utf-8";
  response.set_content(std::string(asset->bytes), type);
  if (asset->content_type == "text/html") {
    response.set_header("Content-Security-Policy", page_security_policy());
    response.set_header("X-Frame-Options", "DENY");  // frame-ancestors for older browsers
    response.set_header("Referrer-Policy", "no-referrer");
  }
  // The page itself may change with a new server; three.js is pinned by its path, and the
  // example mesh (106 KB) does not change with the page's code.
  const bool fixed =
      request.path.starts_with("/web/three/") || request.path.starts_with("/examples/");
  response.set_header("Cache-Control", fixed ? "public, max-age=86400" : "no-cache");
}

}  // namespace

// /healthz, /readyz and /metrics: on the API's port, and alone on the health port.
static void install_probes(httplib::Server& http, Backend& service) {
  http.Get("/healthz", [](const httplib::Request&, httplib::Response& response) {
    send_json(response, 200, {{"status", "ok"}});
  });
  http.Get(
      "/readyz", guarded([&service](const httplib::Request&, httplib::Response& response) {
        if (service.draining())
          throw Problem(503, "shutting_down", "Shutting down", "the server is draining its jobs");
        if (!service.ready())
          throw Problem(503, "queue_unavailable", "Job queue unavailable",
                        "the shared job queue cannot be reached");
        const auto counts = service.queue().counts();
        send_json(response, 200,
                  {{"status", "ready"}, {"queued", counts.queued}, {"running", counts.running}});
      }));
  http.Get("/metrics", guarded([&service](const httplib::Request&, httplib::Response& response) {
             service.queue().evict();
             response.set_content(service.metrics().render(service.queue().counts(),
                                                           service.settings().queue_capacity,
                                                           service.settings().workers),
                                  "text/plain; version=0.0.4; charset=utf-8");
           }));
}

void install_health(GuardedServer& http, Backend& service) {
  // Two threads, and short timeouts: a probe is a small GET from a kubelet or a load
  // balancer, and nothing here may be held long by whoever reaches the port. No cap per
  // address: the probes all come from one.
  http.new_task_queue = [] { return new httplib::ThreadPool(2); };
  ConnectionLimits limits;
  limits.header_timeout_seconds = limits.body_timeout_seconds = 2;
  limits.max_connections_per_address = 0;
  http.set_connection_limits(limits);
  http.set_payload_max_length(0);
  http.set_read_timeout(std::chrono::seconds(2));
  http.set_write_timeout(std::chrono::seconds(2));
  http.set_keep_alive_timeout(1);
  http.set_tcp_nodelay(true);
  install_probes(http, service);
}

void install_api(GuardedServer& http, Backend& service) {
  const ApiSettings& config = service.settings();
  ConnectionLimits limits = config.connection;
  limits.exempt = config.trusted_proxies;
  limits.max_body_bytes = config.max_body_bytes;
  http.set_connection_limits(std::move(limits));
  http.set_refusal_observer([&service](const std::string& slug, const std::string& address) {
    service.metrics().rejected(slug);
    log_event({{"event", "connection_refused"}, {"problem", slug}, {"remote", address}});
  });
  const size_t http_threads = static_cast<size_t>(config.http_threads);
  http.new_task_queue = [http_threads] { return new httplib::ThreadPool(http_threads); };
  http.set_payload_max_length(config.max_body_bytes);
  const auto to_duration = [](double s) {
    return std::chrono::microseconds(static_cast<long long>(s * 1e6));
  };
  http.set_read_timeout(to_duration(config.read_timeout_seconds));
  http.set_write_timeout(to_duration(config.read_timeout_seconds));
  http.set_keep_alive_timeout(
      static_cast<time_t>(std::max(1.0, config.keep_alive_timeout_seconds)));
  http.set_keep_alive_max_count(100);
  // Without it a small response waits for the client's delayed ACK: 40 ms per request.
  http.set_tcp_nodelay(true);
  // Connections are held by one event thread while requests arrive and slow clients
  // read; the pool's threads run handlers only (api/event_front.h).
  FrontSettings front;
  front.threads = http_threads;
  front.max_connections = config.max_connections;
  front.request_buffer_bytes = config.request_buffer_bytes;
  front.pace.min_bytes_per_second = config.response_min_bytes_per_second;
  http.use_event_front(front);

  http.set_pre_routing_handler([&service](const httplib::Request& request,
                                          httplib::Response& response) {
    // With API keys every /v1 route but the API's own description needs a valid key,
    // checked before any body is read, and so does /metrics on this port (queue depths,
    // tenants' activity): the health port serves it openly to the internal network.
    // Preflights carry no credentials (CORS).
    const bool needs_key =
        (request.path.starts_with("/v1/") && request.path != "/v1/openapi.yaml") ||
        request.path == "/metrics";
    if (service.api_keys().enabled() && needs_key && request.method != "OPTIONS" &&
        !service.api_keys().tenant_for(request.get_header_value("Authorization"))) {
      response.set_header("WWW-Authenticate", "Bearer");
      send_problem(response,
                   Problem(401, "unauthorized", "API key required",
                           request.has_header("Authorization")
                               ? "the API key is not valid"
                               : "send your API key as 'Authorization: Bearer KEY'"),
                   request.path);
      return httplib::Server::HandlerResponse::Handled;
    }
    // cpp-httplib builds a multipart body in memory for every range asked for: thousands
    // of overlapping ranges turned an 8 KB GET into hundreds of MB. One range (resuming
    // a download) is served; more are refused before any handler runs.
    // The pre-routing handler runs before cpp-httplib reads the body, so bodies that
    // could exceed max_body_bytes unseen are refused here: chunked bodies (0.11.4 does
    // not apply the payload limit to them), compressed ones (it inflates gzip without
    // limit: 8 MB became 8 GiB), and POSTs without a length (it waited 30 s for them).
    if (request.method == "POST" || request.method == "PUT") {
      if (request.has_header("Transfer-Encoding") || !request.has_header("Content-Length")) {
        send_problem(response, Problem(411, "length_required", "Length required",
                                       "send the body with a Content-Length header (chunked "
                                       "transfer encoding is not accepted)"));
        return httplib::Server::HandlerResponse::Handled;
      }
      if (request.has_header("Content-Encoding") &&
          request.get_header_value("Content-Encoding") != "identity") {
        send_problem(response,
                     Problem(415, "unsupported_content_encoding", "Unsupported content encoding",
                             "send the body uncompressed (Draco-compressed glTF is "
                             "the compact form this service reads)"));
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    // cpp-httplib applies the parsed ranges to whatever the response is, this 416
    // included, so they are dropped here (the request is httplib's own non-const object,
    // handed over as const).
    if (request.ranges.size() > 1) {
      const size_t count = request.ranges.size();
      const_cast<httplib::Request&>(request).ranges.clear();
      send_problem(response,
                   Problem(416, "too_many_ranges", "Range not satisfiable",
                           "at most one byte range per request, got " + std::to_string(count)));
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  http.set_post_routing_handler(
      [&config](const httplib::Request& request, httplib::Response& response) {
        // Every body is what its Content-Type says: no browser guesses an artifact or a
        // problem+json into a script or a page.
        response.set_header("X-Content-Type-Options", "nosniff");
        add_cors_headers(config.cors_origins, request, response);
      });
  // Preflight for any path: what a browser may send cross-origin.
  http.Options(R"(/.*)", [&config](const httplib::Request&, httplib::Response& response) {
    response.status = 204;
    response.set_header("Allow", "GET, POST, DELETE, OPTIONS");
    if (config.cors_origins.empty()) return;
    response.set_header("Access-Control-Allow-Methods", "GET, POST, DELETE, OPTIONS");
    response.set_header("Access-Control-Allow-Headers",
                        "Content-Type, Prefer, Authorization, Idempotency-Key");
    response.set_header("Access-Control-Max-Age", "600");
  });
  http.set_logger([&service](const httplib::Request& request, const httplib::Response& response) {
    // A request the connection limits refused is logged and counted once, as
    // connection_refused; the library still calls this for it, with a status of its own.
    const ServedConnection* stream = GuardedServer::stream_of_this_thread();
    if (stream && stream->refused()) return;
    service.metrics().request(response.status);
    // Timed from the request's first bytes, which the connection saw. Requests the
    // library gives up on before routing (a malformed request line) carry no remote
    // address: the connection has it.
    const Clock::time_point started = stream ? stream->request_start() : Clock::now();
    std::string remote = client_address(service.settings(), request);
    if (remote.empty() && stream) remote = stream->peer_address();
    nlohmann::json line = {
        {"event", "request"},
        {"method", request.method},
        {"path", request.path},
        {"status", response.status},
        {"ms", rounded_seconds(
                   std::chrono::duration<double, std::milli>(Clock::now() - started).count())},
        {"bytes_in", request.body.size()},
        {"bytes_out", bytes_out(response)},
        {"remote", remote}};
    if (response.has_header("Spheremap-Job"))
      line["job"] = response.get_header_value("Spheremap-Job");
    log_event(std::move(line));
  });
  http.set_exception_handler(
      [](const httplib::Request& request, httplib::Response& response, std::exception_ptr error) {
        std::string what = "unknown exception";
        try {
          std::rethrow_exception(error);
        } catch (const std::bad_alloc&) {
          send_problem(response, out_of_memory_problem(), request.path);
          return;
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        log_event({{"event", "handler_exception"}, {"path", request.path}, {"what", what}});
        send_problem(response,
                     Problem(500, "internal", "Internal error",
                             "the server failed to handle this request; it is logged"),
                     request.path);
      });
  http.set_error_handler(httplib::Server::HandlerWithResponse([&config](
                                                                  const httplib::Request& request,
                                                                  httplib::Response& response) {
    if (!response.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    std::string detail = status_title(response.status);
    std::string slug = "http_" + std::to_string(response.status);
    if (response.status == 404 && !allowed_methods(request.path).empty()) {
      response.status = 405;
      response.set_header("Allow", allowed_methods(request.path));
      slug = "method_not_allowed";
      detail = request.method + " is not allowed on " + request.path.substr(0, 200) + "; use " +
               allowed_methods(request.path);
    } else if (response.status == 404) {
      slug = "not_found";
      detail = "no route for " + request.method + " " + request.path.substr(0, 200) +
               "; see /v1/openapi.yaml";
    } else if (response.status == 413 && request.get_header_value("Content-Type")
                                             .starts_with("application/x-www-form-urlencoded")) {
      // httplib refuses form bodies over 8 KB itself; the real mistake is the type.
      response.status = 415;
      slug = "unsupported_media_type";
      detail = kFormEncodedHint;
    } else if (response.status == 413) {
      slug = "too_large";
      detail = "the request body is over max_body_bytes (" + std::to_string(config.max_body_bytes) +
               " bytes)";
    }
    send_problem(response, Problem(response.status, slug, status_title(response.status), detail),
                 request.path);
    return httplib::Server::HandlerResponse::Handled;
  }));

  install_probes(http, service);
  http.Get("/", guarded(serve_asset));
  http.Get(R"(/web/[A-Za-z0-9_./-]+)", guarded(serve_asset));
  http.Get(R"(/examples/[A-Za-z0-9_.-]+)", guarded(serve_asset));
  http.Get("/v1/openapi.yaml", [](const httplib::Request&, httplib::Response& response) {
    response.set_content(kOpenApiYaml, "application/yaml");
  });
  http.Post("/v1/jobs",
            guarded([&service](const httplib::Request& request, httplib::Response& response) {
              post_job(service, request, response);
            }));
  auto sync_waiting = std::make_shared<std::atomic<int>>(0);
  http.Post("/v1/map", guarded([&service, sync_waiting](const httplib::Request& request,
                                                        httplib::Response& response) {
              post_map(service, *sync_waiting, request, response);
            }));
  http.Get(std::string("/v1/jobs/") + kJobId,
           guarded([&service](const httplib::Request& request, httplib::Response& response) {
             const std::shared_ptr<Job> job = find_job(service, request);
             send_json(response, 200, job_json(*job, service.queue().queue_position(*job)));
           }));
  auto event_streams = std::make_shared<EventStreamSlots>();
  http.Get(std::string("/v1/jobs/") + kJobId + "/events",
           guarded([&service, event_streams](const httplib::Request& request,
                                             httplib::Response& response) {
             stream_job_events(service, find_job(service, request), tenant_of(service, request),
                               response, event_streams);
           }));
  http.Get(std::string("/v1/jobs/") + kJobId + "/artifacts/([A-Za-z0-9_.-]+)",
           guarded([&service](const httplib::Request& request, httplib::Response& response) {
             get_artifact(service, request, response);
           }));
  http.Delete(std::string("/v1/jobs/") + kJobId,
              guarded([&service](const httplib::Request& request, httplib::Response& response) {
                delete_job(service, request, response);
              }));
}

}  // namespace spheremap::api
