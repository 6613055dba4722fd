// A node's workers on the Redis queue: `count` threads, each claiming one job at a time
// from the shared stream and running it in its own worker process (worker_process.h),
// while a companion thread keeps the claim alive (heartbeat), publishes progress and
// watches for a client's cancel.
//
// What happens to a job on this node:
//  - it ends (succeeded, failed, cancelled): results stored, entry acknowledged;
//  - its worker process dies (crash, OOM kill, SIGKILL): the job goes back to the queue
//    for another try while attempts remain, then fails as `worker_crashed` (a poison job);
//  - the whole node dies: its heartbeats stop and another node reclaims the job after
//    the visibility timeout;
//  - the node is told to stop (SIGTERM): running jobs get the grace period to finish, then
//    go back to the queue (the attempt is not counted) for another node.
// Redis unreachable: the thread retries every second; finished results are held until
// Redis takes them (the entry stays pending, so nothing is lost either way).
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/job_runner.h"
#include "server/memory_budget.h"
#include "server/redis_queue.h"
#include "server/worker_process.h"

namespace spheremap::server {

class RedisWorkers {
 public:
  using Observer = std::function<void(const std::shared_ptr<Job>&, JobStatus)>;

  // `isolation_thread`: run jobs in this process (worker_isolation "thread"). Each job is
  // charged against `budget` (the node's) before it runs.
  RedisWorkers(RedisJobQueue& queue, int count, RunLimits run, WorkerLimits process,
               bool isolation_thread, MemoryBudget& budget, Observer observer);
  ~RedisWorkers();  // stop(0)

  // Claims no more jobs; waits up to `grace_seconds` for running ones, then puts them
  // back in the queue; joins the threads. Safe to call more than once.
  void stop(double grace_seconds);
  // Ends the grace period now (a second signal).
  void release_now();
  size_t running() const {
    std::lock_guard lock(mutex_);
    return jobs_.size();
  }

 private:
  void work(int index);
  void run_one(RedisConnection& redis, RedisConnection& beat, const std::string& consumer,
               const RedisJobQueue::Delivery& delivery, WorkerProcess* process);
  // Retries `action` every second while Redis is unreachable, until it succeeds or the
  // node stops for good (then the entry stays pending and another node takes over).
  template <typename Action>
  bool persist(Action action);

  RedisJobQueue& queue_;
  MemoryBudget& budget_;
  const RunLimits run_;
  const WorkerLimits process_;
  const bool isolation_thread_;
  const Observer observer_;
  const std::string node_;  // host:pid, the consumer names' stem
  std::atomic<bool> stopping_{false}, releasing_{false}, abandoned_{false};
  mutable std::mutex mutex_;
  std::condition_variable idle_cv_;
  std::vector<Job*> jobs_;  // running here now (guarded by mutex_)
  std::vector<std::thread> threads_;
};

}  // namespace spheremap::server
