// The redis:// backend of JobQueue: jobs shared by every replica and worker node on one
// Redis. Any replica answers for any job; any worker node runs any job; a job whose
// worker node dies is finished by another one.
//
// What lives in Redis (every key under "spheremap:"):
//   jobs                 a stream, one entry per job to run, read by the consumer group
//                        "workers". An entry is pending while a worker runs its job;
//                        the worker's heartbeat (XCLAIM ... JUSTID) keeps it fresh, and
//                        an entry silent for visibility_timeout_seconds is reclaimed by
//                        another worker (XAUTOCLAIM): its node died.
//   job:ID               a hash: status, tenant, times, input summary, options, progress,
//                        metrics, error, artifact list, attempts, cancel flag.
//   spec:ID              the prepared request (worker_protocol's encoding), until it ends.
//   files:ID             a hash of artifact name -> bytes, once it has succeeded.
//   gone:ID              set when a job ends, outlives its results by a day: 410, not 404.
//   queued, tenant:T:queued  sorted sets (by creation) of queued ids: capacity, quotas
//                        and queue positions, cluster-wide.
//   finished, sizes, result_bytes  finished ids by end time and their artifact bytes:
//                        the TTL and the result memory cap, cluster-wide.
//   count:STATUS, count:evicted  totals for /metrics.
//   owners, tenant_bytes, tenant:T:finished  each finished id's tenant, each tenant's
//                        result bytes and finished ids by end time: tenant_result_memory_bytes.
//   idem:N:TENANT:KEY    the job a tenant's Idempotency-Key made (N: the tenant's length).
//   void:ID              a submission the API gave up on (503): it refuses itself if late.
// Every change that must be atomic (admission, start, finish, cancel, eviction) is one
// Lua script, so replicas never race each other.
//
// Redis unreachable: the routes' calls throw QueueUnavailable (503 + Retry-After) and
// readiness fails; nothing is accepted that Redis did not store, and nothing answered 503
// is stored: a submission carries a deadline in Redis's clock (half its timeout) past
// which it refuses itself, and one whose answer was lost is settled (stored, or voided).
// For jobs to survive a restart of Redis itself, Redis must persist (appendonly yes).
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <set>

#include "server/api_types.h"
#include "server/redis_connection.h"
#include "server/shared_bytes_cache.h"

namespace spheremap::server {

struct RedisQueueLimits {
  size_t queue_capacity = 32;
  size_t tenant_max_queued = 16;
  double result_ttl_seconds = 3600;
  size_t result_memory_bytes = 1u << 30;
  size_t max_jobs_kept = 10000;
  double visibility_timeout_seconds = 30;
  int max_attempts = 3;
  size_t tenant_max_running = 0;  // jobs of one tenant running at once, cluster-wide
  size_t tenant_result_memory_bytes = 256u << 20;  // finished results kept per tenant
  // Commands that carry a payload (a submission's prepared input, a job's results) may
  // take this long, plus the per-MiB share for their size, before Redis counts as
  // unavailable (other commands: 2 s).
  double payload_timeout_seconds = 5;
  double payload_timeout_seconds_per_mib = 0.25;
};

class RedisJobQueue : public JobQueue {
 public:
  // Called after a status change this process made (submission here, a start or an end
  // on this node's workers), outside any lock.
  using Observer = std::function<void(const std::shared_ptr<Job>&, JobStatus)>;

  RedisJobQueue(RedisAddress address, RedisQueueLimits limits, Observer observer);

  // JobQueue, for the routes (throw QueueUnavailable while Redis cannot be reached).
  // A submission whose answer is lost (a timeout) is settled before it throws: found
  // stored, it is accepted; otherwise it is made void, so that a 503 means "not stored".
  Admission submit(std::unique_ptr<JobSpec> spec, std::shared_ptr<Job>& job) override;
  std::shared_ptr<Job> replay(const std::string& tenant, const std::string& key) override;
  Lookup find(const std::string& id) override;
  std::shared_ptr<Job> wait(const std::shared_ptr<Job>& job, double seconds) override;
  size_t queue_position(const Job& job) override;
  // Fetched through downloads_: parallel requests for one artifact share one fetch.
  std::optional<Artifact> artifact(const Job& job, const std::string& name) override;
  // Built from the fetched .glb once and kept in downloads_ (bounded), not with the job.
  SharedBytes gltf_view(Job& job, const std::string& glb_name) override;
  bool cancel(const std::shared_ptr<Job>& job, const std::string& reason) override;
  bool remove(const std::string& id) override;
  bool accepting() const override;  // not draining, and Redis answered within the last second
  size_t queued() override;
  void evict() override;
  StoreCounts counts() override;
  void stop_accepting() { accepting_ = false; }

  // The workers' side. Each worker thread passes its own connection.
  struct Delivery {
    std::string entry, id;  // the stream entry and the job it names
  };
  // The next job for `consumer`: first one abandoned by a dead worker, else a new one,
  // waiting up to `block_seconds`; nullopt when there is none.
  std::optional<Delivery> claim(RedisConnection& redis, const std::string& consumer,
                                double block_seconds);
  enum class Start { kRun, kSkip, kLater, kPoison };
  // Marks the job running on `node` and counts the attempt. kSkip: it ended or vanished
  // meanwhile (the entry is acknowledged); kLater: its tenant runs tenant_max_running
  // jobs already (it stays queued, behind the others); kPoison: its workers died
  // max_attempts times.
  Start start(RedisConnection& redis, const Delivery& delivery, const std::string& node,
              int& attempts);
  // The job as a worker runs it: the snapshot plus its spec (nullptr when the spec is gone).
  std::shared_ptr<Job> load(RedisConnection& redis, const std::string& id, bool with_spec);
  // Keeps the entry from being reclaimed; publishes progress while the job runs; returns
  // whether a client asked to cancel the job. Also beats while the result is stored.
  bool heartbeat(RedisConnection& redis, const std::string& consumer, const Delivery& delivery,
                 const Job& job);
  // Stores what the job made and its verdict, acknowledges the entry, evicts over the caps.
  // Safe to call again after a RedisUnavailable (the workers retry it): results already
  // staged are not sent again. Results Redis has no memory for fail the job as
  // result_storage_full (507).
  void finish(RedisConnection& redis, const Delivery& delivery, Job& job, JobStatus status);
  // Puts a running job back in the queue (this node stops, or its worker process died and
  // attempts remain); `count_attempt` false undoes the attempt (a drain is not its fault).
  void release(RedisConnection& redis, const Delivery& delivery, bool count_attempt);

  const RedisQueueLimits& limits() const { return limits_; }
  // Every process on one Redis must apply the same limits (API replicas at admission,
  // worker nodes when they store results). Publishes this process's and returns the
  // limits the previous process to start published when they differ ("" when they agree,
  // or when none are known yet). Throws QueueUnavailable.
  std::string publish_limits();
  const RedisAddress& address() const { return pool_.address(); }
  // Waits (2 s at most) while this process is submitting job `id` and has not told the
  // observer yet: a worker of the same process calls it before it tells "running", so
  // that the job's lines come in order ("queued" first).
  void wait_until_told(const std::string& id);

 private:
  // Marks job `id` as being submitted by this process until destroyed.
  class Telling {
   public:
    Telling(RedisJobQueue& queue, std::string id);
    ~Telling();
    Telling(const Telling&) = delete;
    Telling& operator=(const Telling&) = delete;

   private:
    RedisJobQueue& queue_;
    std::string id_;
  };

  template <typename Body>
  auto with_redis(Body body);
  // How long a command carrying `bytes` may take.
  double payload_timeout(size_t bytes) const;
  // The largest value Redis takes (its proto-max-bulk-len; 512 MiB unless it says).
  size_t max_value_bytes(RedisConnection& redis, double timeout_seconds);
  // After a submission of `id` lost its answer: kStored, or kNotStored and now never will
  // be (its void marker is set, or its deadline has passed), or kUnknown when Redis does
  // not answer for the whole window (logged as admission_unsettled).
  enum class Settled { kStored, kNotStored, kUnknown };
  Settled settle(const std::string& id, int64_t deadline_ms);
  // Writes a finished job's artifacts under `staged`, unless an earlier try already did.
  void stage_results(RedisConnection& redis, const std::string& id, const std::string& staged,
                     const std::vector<std::string>& files, size_t bytes);
  std::shared_ptr<Job> snapshot(RedisConnection& redis, const std::string& id, bool& gone);
  void ensure_group(RedisConnection& redis);
  void evict(RedisConnection& redis);

  const RedisQueueLimits limits_;
  const Observer observer_;
  mutable RedisPool pool_;
  std::atomic<bool> accepting_{true};
  mutable std::atomic<int64_t> last_ping_ok_ms_{0}, last_ping_ms_{0};
  std::atomic<size_t> max_value_bytes_{0};  // 0 = not asked yet
  std::mutex telling_mutex_;
  std::condition_variable told_cv_;
  std::set<std::string> telling_;  // jobs submitted here whose "queued" is not told yet
  SharedBytesCache downloads_;     // artifacts and .gltf views this process has served
};

}  // namespace spheremap::server
