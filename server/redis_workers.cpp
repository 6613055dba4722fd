#include "server/redis_workers.h"

#include <unistd.h>

#include <algorithm>
#include <functional>
#include <optional>

#include "api/log.h"
#include "server/job_guard.h"
#include "server/job_memory.h"

namespace spheremap::server {
namespace {

using namespace std::chrono_literals;

std::string node_name() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return std::string(host) + ":" + std::to_string(getpid());
}

// Runs `action` when the scope ends, however it ends.
class ScopeExit {
 public:
  explicit ScopeExit(std::function<void()> action) : action_(std::move(action)) {}
  ~ScopeExit() { action_(); }
  ScopeExit(const ScopeExit&) = delete;
  ScopeExit& operator=(const ScopeExit&) = delete;

 private:
  std::function<void()> action_;
};

void log_job(const char* what, const std::string& id, const std::string& detail = "") {
  nlohmann::json line = {{"event", what}, {"job", id}};
  if (!detail.empty()) line["detail"] = detail;
  log_event(std::move(line));
}

}  // namespace

RedisWorkers::RedisWorkers(RedisJobQueue& queue, int count, RunLimits run, WorkerLimits process,
                           bool isolation_thread, MemoryBudget& budget, Observer observer)
    : queue_(queue),
      budget_(budget),
      run_(run),
      process_(std::move(process)),
      isolation_thread_(isolation_thread),
      observer_(std::move(observer)),
      node_(node_name()) {
  for (int i = 0; i < count; ++i) threads_.emplace_back([this, i] { work(i); });
}

RedisWorkers::~RedisWorkers() {
  stop(0);
}

template <typename Action>
bool RedisWorkers::persist(Action action) {
  for (bool logged = false;; std::this_thread::sleep_for(1s)) {
    try {
      action();
      return true;
    } catch (const RedisUnavailable& e) {
      if (abandoned_) return false;
      if (!logged) log_event({{"event", "redis_unavailable"}, {"error", e.what()}});
      logged = true;
    }
  }
}

void RedisWorkers::work(int index) {
  const std::string consumer = node_ + ":" + std::to_string(index);
  RedisConnection redis(queue_.address());
  RedisConnection beat(queue_.address());  // the companion's, kept from job to job
  std::optional<WorkerProcess> process;
  if (!isolation_thread_) process.emplace(process_);
  bool unreachable = false;
  while (!stopping_) {
    try {
      const auto delivery = queue_.claim(redis, consumer, 1.0);
      if (unreachable) log_event({{"event", "redis_reachable"}, {"consumer", consumer}});
      unreachable = false;
      if (delivery) run_one(redis, beat, consumer, *delivery, process ? &*process : nullptr);
    } catch (const RedisUnavailable& e) {
      if (!unreachable) log_event({{"event", "redis_unavailable"}, {"error", e.what()}});
      unreachable = true;
      std::this_thread::sleep_for(1s);
    } catch (const std::exception& e) {
      log_event({{"event", "worker_error"}, {"consumer", consumer}, {"error", e.what()}});
      std::this_thread::sleep_for(1s);
    }
  }
  // A consumer with nothing pending is forgotten, so the group lists live workers only.
  try {
    redis.command({"XGROUP", "DELCONSUMER", "spheremap:jobs", "workers", consumer});
  } catch (const std::exception&) {
  }
}

void RedisWorkers::run_one(RedisConnection& redis, RedisConnection& beat,
                           const std::string& consumer, const RedisJobQueue::Delivery& delivery,
                           WorkerProcess* process) {
  int attempts = 0;
  const RedisJobQueue::Start start = queue_.start(redis, delivery, node_, attempts);
  if (start == RedisJobQueue::Start::kSkip) return;
  if (start == RedisJobQueue::Start::kLater) {
    // Only jobs of tenants at their cap may be waiting: do not spin on them.
    std::this_thread::sleep_for(50ms);
    return;
  }
  std::shared_ptr<Job> job;
  std::string unreadable;
  try {
    job = queue_.load(redis, delivery.id, start == RedisJobQueue::Start::kRun);
  } catch (const RedisUnavailable&) {
    throw;
  } catch (const std::exception& e) {
    // An input this build cannot decode (a node of another version during a rolling
    // deploy, or a bug): fail the job now rather than let it go round the nodes.
    unreadable = e.what();
    job = queue_.load(redis, delivery.id, false);
  }
  if (!job) return;  // removed meanwhile; the entry is skipped when reclaimed
  if (stopping_) {   // claimed while this node began to stop: another node takes it
    persist([&] { queue_.release(redis, delivery, false); });
    return;
  }
  auto fail = [&](JobError error) {
    job->error = std::move(error);
    persist([&] { queue_.finish(redis, delivery, *job, JobStatus::kFailed); });
    {
      std::lock_guard lock(job->mutex);
      job->status = JobStatus::kFailed;
      job->finished = Clock::now();
    }
    if (observer_) observer_(job, JobStatus::kFailed);
  };
  if (start == RedisJobQueue::Start::kPoison)
    return fail({500, "worker_crashed", "Worker crashed",
                 "the job's worker died " + std::to_string(attempts) +
                     " times (crash, memory or CPU limit, or its node was lost); it is not "
                     "retried again"});
  if (!unreadable.empty())
    return fail(
        {500, "internal", "Internal error", "the job's input cannot be read: " + unreadable});
  if (!job->spec) return fail({500, "internal", "Internal error", "the job's input is missing"});

  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(job.get());
  }
  queue_.wait_until_told(job->id);  // submitted by this process: "queued" is logged first
  if (observer_) observer_(job, JobStatus::kRunning);
  // The companion: heartbeat, progress and the client's cancel, every 250 ms; woken at
  // once when the job ends, so that a short job's answer does not wait out the interval.
  std::mutex companion_mutex;
  std::condition_variable companion_cv;
  bool done = false;
  std::atomic<bool> client_cancel{false};
  std::thread companion([&] {
    std::unique_lock lock(companion_mutex);
    while (!companion_cv.wait_for(lock, 250ms, [&] { return done; })) {
      try {
        if (queue_.heartbeat(beat, consumer, delivery, *job)) client_cancel = job->cancel = true;
      } catch (const std::exception&) {
        // Redis away for a moment: the claim is kept by the next beat.
      }
    }
  });
  // The companion beats until the result is stored (or the job released), on every way
  // out: a finish that takes long (a large result, Redis away for a while) keeps its
  // claim, so that no other node takes the job over, runs it again and sends its result
  // a second time.
  const ScopeExit stop_companion([&] {
    {
      std::lock_guard lock(companion_mutex);
      done = true;
    }
    companion_cv.notify_one();
    companion.join();
  });
  const auto charge = charge_job(budget_, *job);
  const JobStatus status =
      run_guarded(*job, [&] { return process ? process->run(*job, run_) : run_job(*job, run_); });
  const bool cancelled_by_client = client_cancel;  // the companion still beats from here on
  {
    std::lock_guard lock(mutex_);
    jobs_.erase(std::find(jobs_.begin(), jobs_.end(), job.get()));
  }
  idle_cv_.notify_all();

  if (releasing_ && !cancelled_by_client) {
    if (persist([&] { queue_.release(redis, delivery, false); }))
      log_job("job_released", job->id, "this node stopped before the job ended");
    return;
  }
  const bool crashed = status == JobStatus::kFailed && job->error &&
                       job->error->problem == "worker_crashed" && !cancelled_by_client;
  if (crashed && attempts < queue_.limits().max_attempts) {
    if (persist([&] { queue_.release(redis, delivery, true); }))
      log_job("job_retried", job->id, job->error->detail);
    return;
  }
  if (crashed) {
    std::lock_guard lock(job->mutex);
    job->error->detail += "; attempt " + std::to_string(attempts) + " of " +
                          std::to_string(queue_.limits().max_attempts) + ", not retried again";
  }
  persist([&] { queue_.finish(redis, delivery, *job, status); });
  {
    std::lock_guard lock(job->mutex);
    job->status = status;
    job->finished = Clock::now();
  }
  if (observer_) observer_(job, status);
}

void RedisWorkers::release_now() {
  releasing_ = true;
  std::lock_guard lock(mutex_);
  for (Job* job : jobs_) job->cancel = true;
}

void RedisWorkers::stop(double grace_seconds) {
  if (threads_.empty()) return;
  stopping_ = true;
  {
    std::unique_lock lock(mutex_);
    idle_cv_.wait_for(lock, std::chrono::duration<double>(grace_seconds),
                      [&] { return jobs_.empty(); });
  }
  release_now();
  {
    // A worker process stops within 100 ms of its cancel; Redis may need a few seconds.
    std::unique_lock lock(mutex_);
    idle_cv_.wait_for(lock, 10s, [&] { return jobs_.empty(); });
  }
  abandoned_ = true;  // whatever still waits for Redis is left pending for another node
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

}  // namespace spheremap::server
