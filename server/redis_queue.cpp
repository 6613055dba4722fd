#include "server/redis_queue.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "api/log.h"
#include "core/io/glb_writer.h"
#include "server/redis_scripts.h"
#include "server/worker_protocol.h"

namespace spheremap::server {
namespace {

const std::string kPrefix = "spheremap:";
// The artifacts and .gltf views an API process keeps after serving them (downloads_).
constexpr size_t kDownloadCacheBytes = size_t{256} << 20;
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
std::string void_key(const std::string& id) {
  return kPrefix + "void:" + id;
}
// The tenant's length first: tenant "a:b" with key "c" is not tenant "a" with key "b:c".
std::string idempotency_key(const std::string& tenant, const std::string& key) {
  return kPrefix + "idem:" + std::to_string(tenant.size()) + ":" + tenant + ":" + key;
}

// Redis refused a write for want of memory (maxmemory with noeviction): retrying now does
// not help, and it is not "Redis unavailable".
bool out_of_memory(const std::exception& e) {
  return std::string(e.what()).find("OOM command not allowed") != std::string::npos;
}

// A void marker outlives any submission that could still arrive late.
constexpr double kVoidSeconds = 86400;

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

// `timeout_seconds` 0: the connection's own.
RedisReply eval(RedisConnection& redis, const char* script, const std::vector<std::string>& keys,
                const std::vector<std::string>& args, double timeout_seconds = 0) {
  const std::string count = std::to_string(keys.size());
  std::vector<std::string_view> argv = {"EVAL", script, count};
  for (const std::string& k : keys) argv.push_back(k);
  for (const std::string& a : args) argv.push_back(a);
  return timeout_seconds > 0 ? redis.command_within(argv, timeout_seconds) : redis.command(argv);
}

// Redis's clock in ms: deadlines Redis checks are set in its own clock, not this machine's.
int64_t redis_time_ms(RedisConnection& redis, double timeout_seconds) {
  const RedisReply time = redis.command_within({"TIME"}, timeout_seconds);
  return time.element(0).integer() * 1000 + time.element(1).integer() / 1000;
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
        job->artifacts.push_back({a.at("name"), a.at("type"), nullptr, a.at("size")});
    }
  }
  job->status = job_status_from(status).value_or(JobStatus::kQueued);
  return job;
}

}  // namespace

RedisJobQueue::RedisJobQueue(RedisAddress address, RedisQueueLimits limits, Observer observer)
    : limits_(limits),
      observer_(std::move(observer)),
      pool_(std::move(address), 16),
      downloads_(kDownloadCacheBytes) {}

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

double RedisJobQueue::payload_timeout(size_t bytes) const {
  return limits_.payload_timeout_seconds +
         limits_.payload_timeout_seconds_per_mib * static_cast<double>(bytes) / (1 << 20);
}

size_t RedisJobQueue::max_value_bytes(RedisConnection& redis, double timeout_seconds) {
  if (const size_t known = max_value_bytes_) return known;
  size_t value = size_t{512} << 20;
  try {
    const RedisReply reply =
        redis.command_within({"CONFIG", "GET", "proto-max-bulk-len"}, timeout_seconds);
    if (reply.size() == 2 && reply.element(1).integer() > 0)
      value = static_cast<size_t>(reply.element(1).integer());
  } catch (const RedisUnavailable&) {
    throw;
  } catch (const std::runtime_error&) {
    // CONFIG renamed or refused (a managed Redis): assume its default.
  }
  max_value_bytes_ = value;
  return value;
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
  const double timeout = payload_timeout(encoded.size());
  const std::string key = spec->idempotency_key.empty()
                              ? std::string()
                              : idempotency_key(fresh->tenant, spec->idempotency_key);
  for (;;) {
    fresh->id = new_job_id();
    const Telling telling(*this, fresh->id);  // until the observer has been told
    bool sent = false;
    int64_t deadline_ms = 0;
    std::optional<RedisReply> result;
    try {
      RedisPool::Lease redis = pool_.take();
      // The rest of the command is small beside the spec; over the cap, Redis would drop
      // the connection, and every retry would too.
      if (encoded.size() + 4096 > max_value_bytes(*redis, timeout)) return Admission::kTooLarge;
      // Past this moment (half the timeout) the submission refuses itself in Redis: once
      // this side has given up on it, it can no longer be stored behind the 503.
      deadline_ms = redis_time_ms(*redis, timeout) + static_cast<int64_t>(timeout * 500);
      sent = true;
      result =
          eval(*redis, redis_scripts::kSubmit,
               {kQueued, tenant_queued_key(fresh->tenant), job_key(fresh->id), spec_key(fresh->id),
                kStream, kPrefix + "seq", void_key(fresh->id), key},
               {fresh->id, std::to_string(limits_.queue_capacity),
                std::to_string(limits_.tenant_max_queued), std::to_string(now), encoded,
                std::to_string(deadline_ms), number(limits_.result_ttl_seconds + 86400), kPrefix,
                // the hash's fields
                "id", fresh->id, "tenant", fresh->tenant, "status", "queued", "created_ms",
                std::to_string(now), "input_vertices", std::to_string(fresh->input_vertices),
                "input_faces", std::to_string(fresh->input_faces), "input_bytes",
                std::to_string(fresh->input_bytes), "input_format", fresh->input_format, "options",
                fresh->options.dump(), "progress", progress_json(fresh->progress), "attempts", "0"},
               timeout);
    } catch (const RedisUnavailable& e) {
      last_ping_ok_ms_ = 0;
      if (!sent) throw QueueUnavailable(e.what());
      switch (settle(fresh->id, deadline_ms)) {
        case Settled::kStored:
          break;  // accepted: only the answer was lost
        case Settled::kNotStored:
          throw QueueUnavailable(std::string(e.what()) + "; the job was not stored");
        case Settled::kUnknown:
          throw AdmissionUnsettled(e.what(), fresh->id);
      }
    } catch (const std::runtime_error& e) {
      if (out_of_memory(e)) return Admission::kStorageFull;
      throw;
    }
    switch (result ? result->element(0).integer() : 0) {
      case 1:
        return Admission::kQueueFull;
      case 2:
        return Admission::kTenantQueueFull;
      case 3:
        continue;  // 128 random bits met an existing id: draw again
      case 4: {
        Lookup earlier = find(result->element(1).text());
        if (!earlier.job) continue;  // evicted since: the key makes a new job
        job = earlier.job;
        return Admission::kReplayed;
      }
      case 5:  // its deadline passed before Redis ran it (a stall): not stored
        throw QueueUnavailable("redis took longer than " + std::to_string(timeout / 2) +
                               " s to admit the job; the job was not stored");
    }
    job = fresh;
    if (observer_) observer_(job, JobStatus::kQueued);
    return Admission::kAccepted;
  }
}

RedisJobQueue::Settled RedisJobQueue::settle(const std::string& id, int64_t deadline_ms) {
  // Asked for as long as the submission itself could take, 5 s at least.
  const double window = std::max(5.0, limits_.payload_timeout_seconds);
  const auto give_up = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(window));
  for (;;) {
    try {
      RedisConnection redis(pool_.address(), 1.0);
      // Past the deadline a late submission refuses itself, so what Redis holds now is
      // final: a read settles it (and works while Redis refuses writes).
      if (redis_time_ms(redis, 1.0) > deadline_ms)
        return redis.command({"EXISTS", job_key(id)}).integer() == 1 ? Settled::kStored
                                                                     : Settled::kNotStored;
      return eval(redis, redis_scripts::kSettle, {job_key(id), void_key(id)},
                  {number(kVoidSeconds)})
                         .text() == "stored"
                 ? Settled::kStored
                 : Settled::kNotStored;
    } catch (const std::exception& e) {
      if (Clock::now() >= give_up) {
        log_event({{"event", "admission_unsettled"}, {"job", id}, {"error", e.what()}});
        return Settled::kUnknown;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
}

std::shared_ptr<Job> RedisJobQueue::replay(const std::string& tenant, const std::string& key) {
  const std::string id = with_redis([&](RedisConnection& redis) {
    return redis.command({"GET", idempotency_key(tenant, key)}).text();
  });
  if (id.empty()) return nullptr;
  return find(id).job;
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
  // A job's artifacts never change once listed: the id and the name name the bytes.
  const SharedBytes bytes = downloads_.get(job.id + "/" + name, [&] {
    return with_redis([&](RedisConnection& redis) -> SharedBytes {
      const RedisReply reply = redis.command({"HGET", files_key(job.id), name});
      if (reply.is_nil()) return nullptr;  // evicted between the view and now
      return share_bytes(reply.text());
    });
  });
  if (!bytes) return std::nullopt;
  return Artifact{name, type, bytes, bytes->size()};
}

SharedBytes RedisJobQueue::gltf_view(Job& job, const std::string& glb_name) {
  {
    std::lock_guard lock(job.mutex);
    if (!is_terminal(job.status)) return nullptr;
  }
  return downloads_.get(job.id + "/" + glb_name + " as .gltf", [&]() -> SharedBytes {
    const std::optional<Artifact> glb = artifact(job, glb_name);
    return glb ? share_bytes(glb_to_gltf(*glb->bytes)) : nullptr;
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
                {kPrefix, "0", "0", "0", "0", id, "0"})
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
        std::to_string(limits_.result_memory_bytes), std::to_string(limits_.max_jobs_kept), "",
        std::to_string(limits_.tenant_result_memory_bytes)});
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
                               {"tenant_result_memory_bytes", limits_.tenant_result_memory_bytes},
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
  return eval(redis, redis_scripts::kHeartbeat, {job_key(delivery.id)}, {progress}).text() == "1";
}

void RedisJobQueue::stage_results(RedisConnection& redis, const std::string& id,
                                  const std::string& staged, const std::vector<std::string>& files,
                                  size_t bytes) {
  // A retry after a lost answer: HSET is atomic, so every field there means all were sent.
  // (Sending them again on every retry re-sent one result hundreds of times while its
  // write could not finish within a fixed 2 s timeout.)
  const size_t count = (files.size() - 2) / 2;
  const bool staged_before =
      static_cast<size_t>(redis.command({"HLEN", staged}).integer()) == count;
  // A job that is no longer running (cancelled, removed, or finished by a worker that
  // reclaimed it) takes nothing from this delivery: nothing to send.
  if (!staged_before && redis.command({"HGET", job_key(id), "status"}).text() == "running") {
    std::vector<std::string_view> argv(files.begin(), files.end());
    redis.command_within(argv, payload_timeout(bytes));
  }
  // A worker that dies before its finish leaves no staged files forever.
  redis.command({"EXPIRE", staged, number(limits_.result_ttl_seconds)});
}

void RedisJobQueue::finish(RedisConnection& redis, const Delivery& delivery, Job& job,
                           JobStatus status) {
  // Written under this delivery's own key: the finish script makes them the job's files
  // only if this worker's result is the one that counts.
  const std::string staged = files_key(delivery.id) + ":" + delivery.entry;
  auto fail_for_storage = [&](JobError error) {
    std::lock_guard lock(job.mutex);
    status = JobStatus::kFailed;
    job.error = std::move(error);
    job.artifacts.clear();
  };
  std::vector<std::string> files = {"HSET", staged};
  size_t bytes = 0;
  {
    std::lock_guard lock(job.mutex);
    for (const Artifact& a : job.artifacts) bytes += a.size;
  }
  // Results larger than the whole cluster's result memory could never be downloaded.
  if (bytes > limits_.result_memory_bytes)
    fail_for_storage({507, "result_too_large", "Results too large to keep",
                      "the job's artifacts take " + std::to_string(bytes) +
                          " bytes; result_memory_bytes is " +
                          std::to_string(limits_.result_memory_bytes)});
  {
    std::lock_guard lock(job.mutex);
    for (const Artifact& a : job.artifacts) files.push_back(a.name), files.push_back(*a.bytes);
  }
  if (files.size() > 2) {
    try {
      stage_results(redis, delivery.id, staged, files, bytes);
    } catch (const RedisUnavailable&) {
      throw;
    } catch (const std::runtime_error& e) {
      if (!out_of_memory(e)) throw;
      // Redis has no room for them now: the job fails rather than offer them again.
      fail_for_storage({507, "result_storage_full", "No room to keep the results",
                        "the shared queue (Redis) is out of memory (maxmemory) and could not "
                        "store the job's " +
                            std::to_string(bytes) + " bytes of artifacts"});
    }
  }
  std::vector<std::string> fields;
  nlohmann::json listed = nlohmann::json::array();
  bytes = 0;
  {
    std::lock_guard lock(job.mutex);
    for (const Artifact& a : job.artifacts) {
      listed.push_back({{"name", a.name}, {"type", a.content_type}, {"size", a.size}});
      bytes += a.size;
    }
    job.progress.stage = std::string(to_string(status));
    fields = {"progress", progress_json(job.progress), "artifacts", listed.dump()};
    if (!job.metrics.is_null()) fields.insert(fields.end(), {"metrics", job.metrics.dump()});
    if (job.error) fields.insert(fields.end(), {"error", error_json(*job.error)});
    if (!job.cancel_reason.empty())
      fields.insert(fields.end(), {"cancel_reason", job.cancel_reason});
  }
  std::vector<std::string> args = {delivery.id,
                                   delivery.entry,
                                   std::string(to_string(status)),
                                   std::to_string(wall_ms()),
                                   number(limits_.result_ttl_seconds),
                                   std::to_string(bytes),
                                   kPrefix + "count:" + std::string(to_string(status)),
                                   kPrefix};
  args.insert(args.end(), fields.begin(), fields.end());
  try {
    eval(redis, redis_scripts::kFinish,
         {job_key(delivery.id), files_key(delivery.id), kFinished, kSizes, kResultBytes, kStream,
          gone_key(delivery.id), spec_key(delivery.id), staged, tenant_running_key(job.tenant)},
         args);
  } catch (const RedisUnavailable&) {
    throw;
  } catch (const std::runtime_error& e) {
    // Out of memory even for the verdict: retried (by the caller) until Redis has room;
    // the script is safe to run twice, and the results are not sent again.
    if (out_of_memory(e)) throw RedisUnavailable(e.what());
    throw;
  }
  // The job is finished; an eviction that fails now runs again with the next finish or
  // /metrics, and must not make the caller retry a finish that is done.
  try {
    evict(redis);
  } catch (const std::exception&) {
  }
}

void RedisJobQueue::release(RedisConnection& redis, const Delivery& delivery, bool count_attempt) {
  eval(redis, redis_scripts::kRelease, {job_key(delivery.id), kQueued, kStream},
       {delivery.id, delivery.entry, kPrefix, count_attempt ? "1" : "0"});
}

}  // namespace spheremap::server
