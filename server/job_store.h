// Every job the service knows: a bounded queue of jobs waiting for a worker, the running
// ones, and finished ones kept for a TTL within a memory cap (oldest evicted first; an
// evicted id is remembered so that a later GET can say 410 Gone). Thread-safe.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "server/api_types.h"

namespace spheremap::server {

struct StoreLimits {
  size_t queue_capacity = 32;
  double result_ttl_seconds = 3600;
  size_t result_memory_bytes = 1u << 30;
  size_t max_jobs_kept = 10000;
  // Per tenant (an API key's tenant, or a client address without keys): jobs waiting, jobs
  // mapping at once (0 = no cap), and bytes of finished results kept (its own oldest are
  // evicted first, never another tenant's).
  size_t tenant_max_queued = 16;
  size_t tenant_max_running = 0;
  size_t tenant_result_memory_bytes = 256u << 20;
};

// The memory:// backend of JobQueue.
class JobStore : public JobQueue {
 public:
  // Called after every status change: for queued and running under the store's lock (so
  // they are told in that order; it must not call the store), for the others outside it.
  using Observer = std::function<void(const std::shared_ptr<Job>&, JobStatus)>;

  JobStore(StoreLimits limits, Observer observer);

  Admission submit(std::unique_ptr<JobSpec> spec, std::shared_ptr<Job>& job) override;

  // Blocks until a job may run (returned as running) or the store is closed (nullptr).
  // Tenants take turns: the next job is the oldest queued one of the tenant with the
  // fewest jobs running (then the one that started a job longest ago), skipping tenants
  // at tenant_max_running; one tenant's many jobs never hold back another's.
  std::shared_ptr<Job> next();
  // A worker is done with a running job: it is in a terminal state now.
  void finish(const std::shared_ptr<Job>& job, JobStatus status);

  std::shared_ptr<Job> replay(const std::string& tenant, const std::string& key) override;
  Lookup find(const std::string& id) override;
  std::shared_ptr<Job> wait(const std::shared_ptr<Job>& job, double seconds) override;
  size_t queue_position(const Job& job) override;
  std::optional<Artifact> artifact(const Job& job, const std::string& name) override;
  // Built once and kept with the job, counted in its result bytes while it is kept.
  SharedBytes gltf_view(Job& job, const std::string& glb_name) override;
  bool cancel(const std::shared_ptr<Job>& job, const std::string& reason) override;
  bool remove(const std::string& id) override;

  void stop_accepting();  // new submissions get kShuttingDown
  bool accepting() const override;
  // Cancels every queued job and asks every running one to stop.
  void cancel_all(const std::string& reason);
  // Waits until nothing is queued or running, or the deadline; true when idle.
  bool wait_idle(Clock::time_point deadline);
  void close();  // next() returns nullptr from now on

  size_t queued() override;
  void evict() override;
  StoreCounts counts() override;

 private:
  struct Tenant {
    size_t queued = 0, running = 0, result_bytes = 0;
    Clock::time_point last_start{};
  };
  void evict_locked(std::vector<std::shared_ptr<Job>>& evicted);
  void evict_job_locked(std::deque<std::shared_ptr<Job>>::iterator at,
                        std::vector<std::shared_ptr<Job>>& evicted);
  void remember_evicted(const std::string& id);
  void forget_idempotency_key(const std::string& id);
  std::shared_ptr<Job> replay_locked(const std::string& tenant, const std::string& key);
  // The queue position of the next job to run, or queue_.end() when none may run now.
  std::deque<std::shared_ptr<Job>>::iterator pick_locked();

  const StoreLimits limits_;
  const Observer observer_;
  mutable std::mutex mutex_;
  std::condition_variable queue_cv_, idle_cv_;
  std::unordered_map<std::string, std::shared_ptr<Job>> jobs_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::deque<std::shared_ptr<Job>> finished_;  // oldest first
  std::deque<std::string> evicted_order_;
  std::unordered_set<std::string> evicted_;
  std::unordered_map<std::string, Tenant> tenants_;
  // Idempotency keys of kept jobs: (tenant, key) -> id, and back, to forget them with it.
  std::map<std::pair<std::string, std::string>, std::string> idempotent_;
  std::unordered_map<std::string, std::pair<std::string, std::string>> idempotency_key_of_;
  size_t running_ = 0, result_bytes_ = 0, evicted_total_ = 0;
  bool accepting_ = true, closed_ = false;
};

}  // namespace spheremap::server
