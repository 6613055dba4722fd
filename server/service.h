// The mapping service without its HTTP front: configuration, the job queue (memory://
// in this process, or redis:// shared by every replica), the workers that drain it (the
// only threads that do mesh work), metrics, and the graceful drain used on SIGTERM. The
// HTTP routes (api/) call into it.
#pragma once

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "server/api_types.h"
#include "server/config.h"
#include "server/job_store.h"
#include "server/memory_budget.h"
#include "server/redis_queue.h"
#include "server/redis_workers.h"

namespace spheremap::server {

class Service : public Backend {
 public:
  // Throws ConfigError for a configuration that cannot run (bad API keys file, no
  // workers on a memory queue).
  explicit Service(ServerConfig config);
  ~Service();  // drains with no grace if drain() was not called
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  const ServerConfig& config() const { return config_; }
  // Backend: what the routes see.
  const ApiSettings& settings() const override { return settings_; }
  JobQueue& queue() override { return *queue_; }
  const ApiKeys& api_keys() const override { return api_keys_; }
  ServiceMetrics& metrics() override { return metrics_; }
  Intake& intake() override { return intake_; }
  bool ready() const override { return queue_->accepting(); }
  bool draining() const override { return drained_; }

  // Stops accepting jobs, lets queued and running jobs finish until `grace_seconds`,
  // cancels what is left, waits for the workers, and stops them. Every accepted job ends
  // in a terminal state. With a Redis queue the jobs belong to the cluster: queued ones
  // stay queued, and running ones go back to the queue after the grace period. Safe to
  // call more than once.
  void drain(double grace_seconds);
  // Ends the grace period at once (a second signal): memory jobs are cancelled, Redis
  // jobs running here go back to the queue.
  void stop_now();

 private:
  void work();
  void observe(const std::shared_ptr<Job>& job, JobStatus status);

  const ServerConfig config_;
  const ApiSettings settings_;  // config_'s part the routes apply
  const ApiKeys api_keys_;      // loaded from config_.api_keys at start (ConfigError if bad)
  ServiceMetrics metrics_;
  Intake intake_;
  MemoryBudget budget_;                   // this node's running jobs, together
  std::unique_ptr<JobStore> memory_;      // memory://
  std::unique_ptr<RedisJobQueue> redis_;  // redis://
  std::unique_ptr<RedisWorkers> redis_workers_;
  JobQueue* queue_ = nullptr;
  std::vector<std::thread> workers_;  // memory:// only
  std::atomic<bool> drained_{false};
};

}  // namespace spheremap::server
