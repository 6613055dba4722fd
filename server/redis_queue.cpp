#include "server/redis_queue.h"

#include <chrono>
#include <thread>

#include "server/redis_scripts.h"
#include "server/worker_protocol.h"

namespace spheremap::server {
namespace {

const std::string kPrefix = "spheremap:";
const std::string kStream = kPrefix + "jobs";
const std::string kQueued = kPrefix + "queued";
const std::string kFinished = kPrefix + "finished";
const std::string kSizes = kPrefix + "sizes";
const std::string kResultBytes = kPrefix + "result_bytes";
const char* const kGroup = "workers";

std::string job_key(const std::string& id) {
  return kPrefix + "job:" + id;
}
std::string spec_key(const std::string& id) {
  return kPrefix + "spec:" + id;
}
std::string files_key(const std::string& id) {
  return kPrefix + "files:" + id;
}
std::string gone_key(const std::string& id) {
  return kPrefix + "gone:" + id;
}
std::string tenant_queued_key(const std::string& tenant) {
  return kPrefix + "tenant:" + tenant + ":queued";
}
std::string tenant_running_key(const std::string& tenant) {
  return kPrefix + "tenant:" + tenant + ":running";
}

int64_t wall_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A wall-clock time in ms as this process's steady clock (the Job's time points).
Clock::time_point steady_from_wall(int64_t ms) {
  return Clock::now() - std::chrono::milliseconds(wall_ms() - ms);
}

std::string number(double value) {
  return std::to_string(static_cast<long long>(value));
}

RedisReply eval(RedisConnection& redis, const char* script, const std::vector<std::string>& keys,
                const std::vector<std::string>& args) {
  const std::string count = std::to_string(keys.size());
  std::vector<std::string_view> argv = {"EVAL", script, count};
  for (const std::string& k : keys) argv.push_back(k);
  for (const std::string& a : args) argv.push_back(a);
  return redis.command(argv);
}

// The job hash as a Job (a view: artifacts listed without their bytes).
std::shared_ptr<Job> job_from_hash(const RedisReply& fields) {
  auto job = std::make_shared<Job>();
  std::string status = "queued";
  for (size_t i = 0; i + 1 < fields.size(); i += 2) {
    const std::string key = fields.element(i).text();
    const std::string value = fields.element(i + 1).text();
    const long long integer = fields.element(i + 1).integer();
    if (key == "id")
      job->id = value;
    else if (key == "tenant")
      job->tenant = value;
    else if (key == "status")
      status = value;
    else if (key == "created_ms") {
      job->created = steady_from_wall(integer);
      job->created_wall = std::chrono::system_clock::time_point(std::chrono::milliseconds(integer));
    } else if (key == "started_ms")
      job->started = steady_from_wall(integer);
    else if (key == "finished_ms")
      job->finished = steady_from_wall(integer);
    else if (key == "input_vertices")
      job->input_vertices = static_cast<size_t>(integer);
    else if (key == "input_faces")
      job->input_faces = static_cast<size_t>(integer);
    else if (key == "input_bytes")
      job->input_bytes = static_cast<size_t>(integer);
    else if (key == "input_format")
      job->input_format = value;
    else if (key == "options")
      job->options = nlohmann::json::parse(value, nullptr, false);
    else if (key == "progress")
      job->progress = progress_from_json(value);
    else if (key == "metrics")
      job->metrics = nlohmann::json::parse(value, nullptr, false);
    else if (key == "error")
      job->error = error_from_json(value);
    else if (key == "cancel_reason")
      job->cancel_reason = value;
    else if (key == "cancel")
      job->cancel = value == "1";
    else if (key == "artifacts") {
      for (const nlohmann::json& a : nlohmann::json::parse(value))
        job->artifacts.push_back({a.at("name"), a.at("type"), "", a.at("size")});
    }
  }
  job->status = job_status_from(status).value_or(JobStatus::kQueued);
  return job;
}

}  // namespace

RedisJobQueue::RedisJobQueue(RedisAddress address, RedisQueueLimits limits, Observer observer)
    : limits_(limits), observer_(std::move(observer)), pool_(std::move(address), 16) {}

// Runs `body` on a pooled connection; Redis out of reach becomes QueueUnavailable.
template <typename Body>
auto RedisJobQueue::with_redis(Body body) {
  try {
    RedisPool::Lease redis = pool_.take();
    return body(*redis);
  } catch (const RedisUnavailable& e) {
    last_ping_ok_ms_ = 0;
    throw QueueUnavailable(e.what());
  }
}

JobQueue::Admission RedisJobQueue::submit(std::unique_ptr<JobSpec> spec,
                                          std::shared_ptr<Job>& job) {
  if (!accepting_) return Admission::kShuttingDown;
  const std::string encoded = encode_request(*spec, 0, 0);
  auto fresh = std::make_shared<Job>();
  fresh->tenant = spec->tenant;
  fresh->input_vertices = spec->input.vertex_count();
  fresh->input_faces = spec->input.face_count();
  fresh->input_bytes = spec->input_bytes;
  fresh->input_format = spec->input_format;
  fresh->options = spec->options_echo;
  const int64_t now = wall_ms();
  fresh->created_wall = std::chrono::system_clock::time_point(std::chrono::milliseconds(now));
  return with_redis([&](RedisConnection& redis) {
    for (;;) {
      fresh->id = new_job_id();
      const Telling telling(*this, fresh->id);  // until the observer has been told
      const RedisReply result = eval(
          redis, redis_scripts::kSubmit,
          {kQueued, tenant_queued_key(fresh->tenant), job_key(fresh->id), spec_key(fresh->id),
           kStream, kPrefix + "seq"},
          {fresh->id, std::to_string(limits_.queue_capacity),
           std::to_string(limits_.tenant_max_queued), std::to_string(now), encoded,
           // the hash's fields
           "id", fresh->id, "tenant", fresh->tenant, "status", "queued", "created_ms",
           std::to_string(now), "input_vertices", std::to_string(fresh->input_vertices),
           "input_faces", std::to_string(fresh->input_faces), "input_bytes",
           std::to_string(fresh->input_bytes), "input_format", fresh->input_format, "options",
           fresh->options.dump(), "progress", progress_json(fresh->progress), "attempts", "0"});
      switch (result.integer()) {
        case 1:
          return Admission::kQueueFull;
        case 2:
          return Admission::kTenantQueueFull;
        case 3:
          continue;  // 128 random bits met an existing id: draw again
      }
      job = fresh;
      if (observer_) observer_(job, JobStatus::kQueued);
      return Admission::kAccepted;
    }
  });
}

std::shared_ptr<Job> RedisJobQueue::snapshot(RedisConnection& redis, const std::string& id,
                                             bool& gone) {
  const RedisReply fields = redis.command({"HGETALL", job_key(id)});
  gone = false;
  if (fields.size() == 0) {
    gone = redis.command({"EXISTS", gone_key(id)}).integer() == 1;
    return nullptr;
  }
  return job_from_hash(fields);
}

JobQueue::Lookup RedisJobQueue::find(const std::string& id) {
  return with_redis([&](RedisConnection& redis) {
    bool gone = false;
    std::shared_ptr<Job> job = snapshot(redis, id, gone);
    return Lookup{job, gone};
  });
}

std::shared_ptr<Job> RedisJobQueue::wait(const std::shared_ptr<Job>& job, double seconds) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(seconds));
  {
    std::lock_guard lock(job->mutex);
    if (is_terminal(job->status)) return job;
  }
  // Polls the status alone, 2 ms apart at first and backing off to 10 ms: the answer
  // leaves at most 10 ms after the job ends (a 50 ms ceiling let a client's next job
  // start late enough to idle a worker: measured 3-6 ms per medium job). One HGET per
  // waiter every 10 ms, and waiters are few: half the HTTP threads for POST /v1/map, a
  // quarter for event streams.
  auto pause = std::chrono::milliseconds(2);
  while (Clock::now() < deadline) {
    std::this_thread::sleep_for(std::min<Clock::duration>(pause, deadline - Clock::now()));
    pause = std::min(pause * 2, std::chrono::milliseconds(10));
    const std::string status = with_redis([&](RedisConnection& redis) {
      return redis.command({"HGET", job_key(job->id), "status"}).text();
    });
    const auto now = job_status_from(status);
    if (!now || is_terminal(*now)) break;  // ended (or removed): read it whole
  }
  Lookup found = find(job->id);
  return found.job ? found.job : job;
}

size_t RedisJobQueue::queue_position(const Job& job) {
  return with_redis([&](RedisConnection& redis) -> size_t {
    const RedisReply rank = redis.command({"ZRANK", kQueued, job.id});
    return rank.is_nil() ? 0 : static_cast<size_t>(rank.integer()) + 1;
  });
}

std::optional<Artifact> RedisJobQueue::artifact(const Job& job, const std::string& name) {
  std::string type;
  {
    std::lock_guard lock(job.mutex);
    for (const Artifact& a : job.artifacts)
      if (a.name == name) type = a.content_type;
  }
  if (type.empty()) return std::nullopt;
  return with_redis([&](RedisConnection& redis) -> std::optional<Artifact> {
    const RedisReply bytes = redis.command({"HGET", files_key(job.id), name});
    if (bytes.is_nil()) return std::nullopt;  // evicted between the view and now
    std::string data = bytes.text();
    const size_t size = data.size();
    return Artifact{name, type, std::move(data), size};
  });
}

bool RedisJobQueue::cancel(const std::shared_ptr<Job>& job, const std::string& reason) {
  const std::string outcome = with_redis([&](RedisConnection& redis) {
    return eval(
               redis, redis_scripts::kCancel,
               {job_key(job->id), kQueued, kFinished, kSizes, gone_key(job->id), spec_key(job->id)},
               {job->id, reason, std::to_string(wall_ms()), number(limits_.result_ttl_seconds),
                kPrefix})
        .text();
  });
  if (outcome == "cancelled") {
    {
      std::lock_guard lock(job->mutex);
      job->status = JobStatus::kCancelled;
      job->cancel_reason = reason;
      job->finished = Clock::now();
      job->progress.stage = "cancelled";
    }
    if (observer_) observer_(job, JobStatus::kCancelled);
  }
  return outcome == "cancelled" || outcome == "stopping";
}

bool RedisJobQueue::remove(const std::string& id) {
  return with_redis([&](RedisConnection& redis) {
    return eval(redis, redis_scripts::kEvict, {kFinished, kSizes, kResultBytes},
                {kPrefix, "0", "0", "0", "0", id})
               .integer() == 1;
  });
}

bool RedisJobQueue::accepting() const {
  if (!accepting_) return false;
  const int64_t now = wall_ms();
  if (now - last_ping_ms_ < 1000) return now - last_ping_ok_ms_ < 1500;
  last_ping_ms_ = now;
  try {
    RedisPool::Lease redis = pool_.take();
    redis->command({"PING"});
    last_ping_ok_ms_ = now;
    return true;
  } catch (const std::exception&) {
    last_ping_ok_ms_ = 0;
    return false;
  }
}

size_t RedisJobQueue::queued() {
  return with_redis([&](RedisConnection& redis) {
    return static_cast<size_t>(redis.command({"ZCARD", kQueued}).integer());
  });
}

void RedisJobQueue::evict(RedisConnection& redis) {
  eval(redis, redis_scripts::kEvict, {kFinished, kSizes, kResultBytes},
       {kPrefix, std::to_string(wall_ms()), number(limits_.result_ttl_seconds * 1000),
        std::to_string(limits_.result_memory_bytes), std::to_string(limits_.max_jobs_kept), ""});
}

void RedisJobQueue::evict() {
  with_redis([&](RedisConnection& redis) { evict(redis); });
}

StoreCounts RedisJobQueue::counts() {
  return with_redis([&](RedisConnection& redis) {
    StoreCounts c;
    c.queued = static_cast<size_t>(redis.command({"ZCARD", kQueued}).integer());
    try {
      // Entries delivered and not acknowledged: jobs running (or awaiting reclaim).
      const RedisReply pending = redis.command({"XPENDING", kStream, kGroup});
      if (pending.size() > 0) c.running = static_cast<size_t>(pending.element(0).integer());
    } catch (const RedisUnavailable&) {
      throw;
    } catch (const std::runtime_error&) {
      // NOGROUP: no worker node has started yet
    }
    const RedisReply totals =
        redis.command({"MGET", kPrefix + "count:succeeded", kPrefix + "count:failed",
                       kPrefix + "count:cancelled", kResultBytes, kPrefix + "count:evicted"});
    c.succeeded = static_cast<size_t>(totals.element(0).integer());
    c.failed = static_cast<size_t>(totals.element(1).integer());
    c.cancelled = static_cast<size_t>(totals.element(2).integer());
    c.result_bytes = static_cast<size_t>(std::max(0LL, totals.element(3).integer()));
    c.evicted = static_cast<size_t>(totals.element(4).integer());
    return c;
  });
}

std::string RedisJobQueue::publish_limits() {
  const nlohmann::json ours = {{"queue_capacity", limits_.queue_capacity},
                               {"tenant_max_queued", limits_.tenant_max_queued},
                               {"tenant_max_running", limits_.tenant_max_running},
                               {"result_ttl_seconds", limits_.result_ttl_seconds},
                               {"result_memory_bytes", limits_.result_memory_bytes},
                               {"max_jobs_kept", limits_.max_jobs_kept},
                               {"visibility_timeout_seconds", limits_.visibility_timeout_seconds},
                               {"max_attempts", limits_.max_attempts}};
  return with_redis([&](RedisConnection& redis) {
    const RedisReply before =
        redis.command({"SET", kPrefix + "limits", ours.dump(), "GET", "EX", "604800"});
    return before.is_nil() || before.text() == ours.dump() ? std::string() : before.text();
  });
}

RedisJobQueue::Telling::Telling(RedisJobQueue& queue, std::string id)
    : queue_(queue), id_(std::move(id)) {
  std::lock_guard lock(queue_.telling_mutex_);
  queue_.telling_.insert(id_);
}

RedisJobQueue::Telling::~Telling() {
  {
    std::lock_guard lock(queue_.telling_mutex_);
    queue_.telling_.erase(id_);
  }
  queue_.told_cv_.notify_all();
}

void RedisJobQueue::wait_until_told(const std::string& id) {
  std::unique_lock lock(telling_mutex_);
  told_cv_.wait_for(lock, std::chrono::seconds(2), [&] { return telling_.count(id) == 0; });
}

// --- the workers' side --------------------------------------------------------------

void RedisJobQueue::ensure_group(RedisConnection& redis) {
  try {
    redis.command({"XGROUP", "CREATE", kStream, kGroup, "0", "MKSTREAM"});
  } catch (const RedisUnavailable&) {
    throw;
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("BUSYGROUP") == std::string::npos) throw;
  }
}

std::optional<RedisJobQueue::Delivery> RedisJobQueue::claim(RedisConnection& redis,
                                                            const std::string& consumer,
                                                            double block_seconds) {
  auto first_entry = [](const RedisReply& entries) -> std::optional<Delivery> {
    for (size_t i = 0; i < entries.size(); ++i) {
      const RedisReply entry = entries.element(i);
      if (entry.size() < 2) continue;  // an entry deleted while pending
      const RedisReply fields = entry.element(1);
      for (size_t f = 0; f + 1 < fields.size(); f += 2)
        if (fields.element(f).text() == "job")
          return Delivery{entry.element(0).text(), fields.element(f + 1).text()};
    }
    return std::nullopt;
  };
  try {
    // A job abandoned by a worker silent for the visibility timeout (its node died).
    const std::string idle = number(limits_.visibility_timeout_seconds * 1000);
    const RedisReply reclaimed =
        redis.command({"XAUTOCLAIM", kStream, kGroup, consumer, idle, "0-0", "COUNT", "1"});
    if (reclaimed.size() >= 2)
      if (auto delivery = first_entry(reclaimed.element(1))) return delivery;
    const std::string block_ms = number(block_seconds * 1000);
    const RedisReply read =
        redis.blocking_command({"XREADGROUP", "GROUP", kGroup, consumer, "COUNT", "1", "BLOCK",
                                block_ms, "STREAMS", kStream, ">"},
                               block_seconds);
    if (read.size() == 0) return std::nullopt;
    return first_entry(read.element(0).element(1));
  } catch (const RedisUnavailable&) {
    throw;
  } catch (const std::runtime_error& e) {
    // NOGROUP: a fresh Redis (or one restarted without its data): make the group.
    if (std::string(e.what()).find("NOGROUP") == std::string::npos) throw;
    ensure_group(redis);
    return std::nullopt;
  }
}

RedisJobQueue::Start RedisJobQueue::start(RedisConnection& redis, const Delivery& delivery,
                                          const std::string& node, int& attempts) {
  const RedisReply result =
      eval(redis, redis_scripts::kStart, {job_key(delivery.id), kQueued, kStream},
           {delivery.id, std::to_string(wall_ms()), std::to_string(limits_.max_attempts), node,
            kPrefix, delivery.entry, std::to_string(limits_.tenant_max_running)});
  const std::string what = result.element(0).text();
  attempts = static_cast<int>(result.element(1).integer());
  if (what == "run") return Start::kRun;
  if (what == "later") return Start::kLater;
  return what == "poison" ? Start::kPoison : Start::kSkip;
}

std::shared_ptr<Job> RedisJobQueue::load(RedisConnection& redis, const std::string& id,
                                         bool with_spec) {
  bool gone = false;
  std::shared_ptr<Job> job = snapshot(redis, id, gone);
  if (!job || !with_spec) return job;
  job->artifacts.clear();
  const RedisReply spec = redis.command({"GET", spec_key(id)});
  if (spec.is_nil()) return job;
  WorkerRequest request = decode_request(spec.text());
  job->spec = std::make_unique<JobSpec>(std::move(request.spec));
  return job;
}

bool RedisJobQueue::heartbeat(RedisConnection& redis, const std::string& consumer,
                              const Delivery& delivery, const Job& job) {
  std::string progress;
  {
    std::lock_guard lock(job.mutex);
    progress = progress_json(job.progress);
  }
  redis.command({"XCLAIM", kStream, kGroup, consumer, "0", delivery.entry, "JUSTID"});
  redis.command({"HSET", job_key(delivery.id), "progress", progress});
  return redis.command({"HGET", job_key(delivery.id), "cancel"}).text() == "1";
}

void RedisJobQueue::finish(RedisConnection& redis, const Delivery& delivery, Job& job,
                           JobStatus status) {
  std::vector<std::string> fields;
  nlohmann::json listed = nlohmann::json::array();
  // Written under this delivery's own key: the finish script makes them the job's files
  // only if this worker's result is the one that counts.
  const std::string staged = files_key(delivery.id) + ":" + delivery.entry;
  std::vector<std::string> files = {"HSET", staged};
  size_t bytes = 0;
  {
    std::lock_guard lock(job.mutex);
    for (const Artifact& a : job.artifacts) {
      listed.push_back({{"name", a.name}, {"type", a.content_type}, {"size", a.bytes.size()}});
      bytes += a.bytes.size();
    }
    // Results larger than the whole cluster's result memory could never be downloaded.
    if (bytes > limits_.result_memory_bytes) {
      status = JobStatus::kFailed;
      job.error = JobError{507, "result_too_large", "Results too large to keep",
                           "the job's artifacts take " + std::to_string(bytes) +
                               " bytes; result_memory_bytes is " +
                               std::to_string(limits_.result_memory_bytes)};
      job.artifacts.clear();
      listed = nlohmann::json::array();
      bytes = 0;
    }
    for (const Artifact& a : job.artifacts) files.push_back(a.name), files.push_back(a.bytes);
    job.progress.stage = std::string(to_string(status));
    fields = {"progress", progress_json(job.progress), "artifacts", listed.dump()};
    if (!job.metrics.is_null()) fields.insert(fields.end(), {"metrics", job.metrics.dump()});
    if (job.error) fields.insert(fields.end(), {"error", error_json(*job.error)});
    if (!job.cancel_reason.empty())
      fields.insert(fields.end(), {"cancel_reason", job.cancel_reason});
  }
  if (files.size() > 2) {
    std::vector<std::string_view> argv(files.begin(), files.end());
    redis.command(argv);
    // A worker that dies before its finish leaves no staged files forever.
    redis.command({"EXPIRE", staged, number(limits_.result_ttl_seconds)});
  }
  std::vector<std::string> args = {delivery.id,
                                   delivery.entry,
                                   std::string(to_string(status)),
                                   std::to_string(wall_ms()),
                                   number(limits_.result_ttl_seconds),
                                   std::to_string(bytes),
                                   kPrefix + "count:" + std::string(to_string(status))};
  args.insert(args.end(), fields.begin(), fields.end());
  eval(redis, redis_scripts::kFinish,
       {job_key(delivery.id), files_key(delivery.id), kFinished, kSizes, kResultBytes, kStream,
        gone_key(delivery.id), spec_key(delivery.id), staged, tenant_running_key(job.tenant)},
       args);
  evict(redis);
}

void RedisJobQueue::release(RedisConnection& redis, const Delivery& delivery, bool count_attempt) {
  eval(redis, redis_scripts::kRelease, {job_key(delivery.id), kQueued, kStream},
       {delivery.id, delivery.entry, kPrefix, count_attempt ? "1" : "0"});
}

}  // namespace spheremap::server
