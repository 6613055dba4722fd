// The mapping service without its HTTP front: configuration, the job store, the worker
// pool that drains it (the only threads that do mesh work), metrics, and the graceful
// drain used on SIGTERM. The HTTP routes (api/) call into it.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

#include "server/api_keys.h"
#include "server/config.h"
#include "server/job_store.h"
#include "server/service_metrics.h"

namespace spheremap::server {

class Service {
 public:
  explicit Service(ServerConfig config);
  ~Service();  // drains with no grace if drain() was not called
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  const ServerConfig& config() const { return config_; }
  JobStore& store() { return store_; }
  const ApiKeys& api_keys() const { return api_keys_; }
  ServiceMetrics& metrics() { return metrics_; }
  bool ready() const { return store_.accepting(); }

  // Stops accepting jobs, lets queued and running jobs finish until `grace_seconds`,
  // cancels what is left, waits for the workers, and stops them. Every accepted job ends
  // in a terminal state. Safe to call more than once.
  void drain(double grace_seconds);

 private:
  void work();
  void observe(const std::shared_ptr<Job>& job, JobStatus status);

  const ServerConfig config_;
  const ApiKeys api_keys_;  // loaded from config_.api_keys at start (ConfigError if bad)
  ServiceMetrics metrics_;
  JobStore store_;
  std::vector<std::thread> workers_;
  std::atomic<bool> drained_{false};
};

}  // namespace spheremap::server
