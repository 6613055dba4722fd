#include "server/service.h"

#include <signal.h>

#include <algorithm>
#include <sstream>

#include "api/log.h"
#include "server/job_guard.h"
#include "server/job_memory.h"
#include "server/job_runner.h"
#include "server/worker_process.h"

namespace spheremap::server {
namespace {

double seconds_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

StoreLimits store_limits(const ServerConfig& c) {
  return {c.queue_capacity,    c.result_ttl_seconds, c.result_memory_bytes,       c.max_jobs_kept,
          c.tenant_max_queued, c.tenant_max_running, c.tenant_result_memory_bytes};
}

RedisQueueLimits redis_limits(const ServerConfig& c) {
  RedisQueueLimits l;
  l.queue_capacity = c.queue_capacity;
  l.tenant_max_queued = c.tenant_max_queued;
  l.result_ttl_seconds = c.result_ttl_seconds;
  l.result_memory_bytes = c.result_memory_bytes;
  l.max_jobs_kept = c.max_jobs_kept;
  l.visibility_timeout_seconds = c.visibility_timeout_seconds;
  l.max_attempts = c.max_attempts;
  l.tenant_max_running = c.tenant_max_running;
  l.tenant_result_memory_bytes = c.tenant_result_memory_bytes;
  l.payload_timeout_seconds = c.redis_payload_timeout_seconds;
  l.payload_timeout_seconds_per_mib = c.redis_payload_timeout_seconds_per_mib;
  return l;
}

ApiSettings api_settings(const ServerConfig& c) {
  ApiSettings s;
  s.http_threads = c.http_threads;
  s.queue_capacity = c.queue_capacity;
  s.tenant_max_queued = c.tenant_max_queued;
  s.max_body_bytes = c.max_body_bytes;
  s.max_vertices = c.max_vertices;
  s.max_faces = c.max_faces;
  s.max_envelope_voxels = c.max_envelope_voxels;
  s.max_resource_bytes = c.max_resource_bytes;
  s.max_image_pixels = c.max_image_pixels;
  s.sync_timeout_seconds = c.sync_timeout_seconds;
  s.keep_alive_timeout_seconds = c.keep_alive_timeout_seconds;
  s.read_timeout_seconds = c.read_timeout_seconds;
  s.connection.header_timeout_seconds = c.header_timeout_seconds;
  s.connection.body_timeout_seconds = c.body_timeout_seconds;
  s.connection.max_header_count = c.max_header_count;
  s.connection.max_header_bytes = c.max_header_bytes;
  s.connection.max_connections_per_address = c.max_connections_per_address;
  s.max_connections = c.max_connections;
  s.request_buffer_bytes =
      c.request_buffer_bytes != 0 ? c.request_buffer_bytes : 4 * c.max_body_bytes;
  s.response_min_bytes_per_second = c.response_min_bytes_per_second;
  s.cors_origins = c.cors_origins;
  std::stringstream proxies(c.trusted_proxies);
  for (std::string proxy; std::getline(proxies, proxy, ',');) {
    proxy.erase(0, proxy.find_first_not_of(' '));
    proxy.erase(proxy.find_last_not_of(' ') + 1);
    if (!proxy.empty()) s.trusted_proxies.push_back(proxy);
  }
  s.workers = c.effective_workers();
  return s;
}

ApiKeys load_api_keys(const std::string& path) {
  if (path.empty()) return ApiKeys();
  try {
    return ApiKeys::load(path);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(e.what());
  }
}

RunLimits run_limits(const ServerConfig& c) {
  return {c.job_time_limit_seconds, c.effective_threads_per_job()};
}

WorkerLimits worker_limits(const ServerConfig& c) {
  return {c.worker_executable, c.effective_worker_memory_bytes(), c.effective_worker_cpu_seconds(),
          std::max<size_t>(c.result_memory_bytes, size_t{1} << 30)};
}

}  // namespace

Service::Service(ServerConfig config)
    : config_(std::move(config)),
      settings_(api_settings(config_)),
      api_keys_(load_api_keys(config_.api_keys)),
      intake_(config_.effective_intake_threads(), config_.intake_timeout_seconds),
      budget_(config_.effective_jobs_memory_bytes()) {
  // A worker process that dies while we write its request must not kill the server.
  signal(SIGPIPE, SIG_IGN);
  auto observer = [this](const std::shared_ptr<Job>& job, JobStatus status) {
    observe(job, status);
  };
  if (config_.shared_queue()) {
    redis_ = std::make_unique<RedisJobQueue>(RedisAddress::parse(config_.queue),
                                             redis_limits(config_), observer);
    queue_ = redis_.get();
    try {
      const std::string theirs = redis_->publish_limits();
      if (!theirs.empty())
        log_event({{"event", "limits_differ"},
                   {"detail",
                    "the process started before this one on the same Redis had other queue "
                    "or result limits; give every replica and worker the same settings"},
                   {"previous", nlohmann::json::parse(theirs, nullptr, false)}});
    } catch (const QueueUnavailable&) {
      // Redis not up yet: the service waits for it; the check is a warning only.
    }
    if (config_.effective_workers() > 0)
      redis_workers_ = std::make_unique<RedisWorkers>(
          *redis_, config_.effective_workers(), run_limits(config_), worker_limits(config_),
          config_.worker_isolation == "thread", budget_, observer);
    return;
  }
  if (config_.effective_workers() == 0)
    throw ConfigError("workers 0 (an API-only node) needs a shared queue (--queue redis://...)");
  memory_ = std::make_unique<JobStore>(store_limits(config_), observer);
  queue_ = memory_.get();
  for (int i = 0; i < config_.effective_workers(); ++i) workers_.emplace_back([this] { work(); });
}

Service::~Service() {
  drain(0);
}

void Service::work() {
  const RunLimits limits = run_limits(config_);
  JobStore& store = *memory_;
  if (config_.worker_isolation == "thread") {
    while (std::shared_ptr<Job> job = store.next()) {
      const auto charge = charge_job(budget_, *job);
      store.finish(job, run_guarded(*job, [&] { return run_job(*job, limits); }));
    }
    return;
  }
  WorkerProcess process(worker_limits(config_));
  while (std::shared_ptr<Job> job = store.next()) {
    const auto charge = charge_job(budget_, *job);
    store.finish(job, run_guarded(*job, [&] { return process.run(*job, limits); }));
  }
}

void Service::observe(const std::shared_ptr<Job>& job, JobStatus status) {
  nlohmann::json line = {{"event", "job"}, {"job", job->id}, {"status", to_string(status)}};
  std::lock_guard lock(job->mutex);
  if (status == JobStatus::kQueued) {
    line["vertices"] = job->input_vertices;
    line["faces"] = job->input_faces;
    line["bytes"] = job->input_bytes;
    metrics_.job_accepted(job->input_bytes, job->input_faces);
  } else if (status == JobStatus::kRunning) {
    line["waited_s"] = rounded_seconds(seconds_between(job->created, *job->started));
  } else {
    const Clock::time_point end = job->finished.value_or(Clock::now());
    const double run = job->started ? seconds_between(*job->started, end) : 0;
    const double wait = seconds_between(job->created, job->started.value_or(end));
    line["run_s"] = rounded_seconds(run);
    line["total_s"] = rounded_seconds(seconds_between(job->created, end));
    if (job->error) {
      line["problem"] = job->error->problem;
      line["detail"] = job->error->detail;
    }
    if (!job->cancel_reason.empty()) line["reason"] = job->cancel_reason;
    if (job->metrics.contains("bijective_as_written"))
      line["bijective_as_written"] = job->metrics["bijective_as_written"];
    metrics_.job_ended(status, run, wait);
  }
  log_event(std::move(line));
}

void Service::stop_now() {
  if (memory_) memory_->cancel_all("the server was told to stop at once (a second signal)");
  if (redis_workers_) redis_workers_->release_now();
}

void Service::drain(double grace_seconds) {
  if (drained_.exchange(true)) return;
  intake_.stop_reading();  // a mesh being read stops within milliseconds: 503 shutting_down
  if (redis_) {
    redis_->stop_accepting();
    const size_t running = redis_workers_ ? redis_workers_->running() : 0;
    log_event({{"event", "draining"}, {"running_here", running}, {"grace_s", grace_seconds}});
    if (redis_workers_) redis_workers_->stop(grace_seconds);
    log_event({{"event", "drained"}});
    return;
  }
  JobStore& store = *memory_;
  store.stop_accepting();
  const auto counts = store.counts();
  log_event({{"event", "draining"},
             {"queued", counts.queued},
             {"running", counts.running},
             {"grace_s", grace_seconds}});
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(grace_seconds));
  if (!store.wait_idle(deadline)) {
    store.cancel_all("the server shut down before the job finished");
    store.wait_idle(Clock::now() + std::chrono::hours(24));  // the engine stops in ms
  }
  store.close();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
  log_event({{"event", "drained"}});
}

}  // namespace spheremap::server
