// Where jobs wait, run and are kept: what the HTTP routes see of the service. Two
// backends: JobStore (memory://, this process only, the default) and RedisJobQueue
// (redis://, shared by every replica and worker node on one Redis). The workers' side
// differs between them (threads that take from the store, or nodes that claim from a
// Redis stream), so it is not part of this interface.
//
// A Job returned here is a view: in memory it is the live object; from Redis it is a
// snapshot read when asked (artifacts listed with their sizes, bytes left in Redis).
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "api/job.h"

namespace spheremap::api {

struct StoreCounts {
  size_t queued = 0, running = 0, succeeded = 0, failed = 0, cancelled = 0;
  size_t result_bytes = 0, evicted = 0;
};

// The queue's backend cannot be reached now (Redis down): the request may be retried.
class QueueUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A submission whose fate is unknown: the backend ran out of reach after it was sent and
// stayed so while it was asked afterwards. The job may exist under `job_id` (rare: Redis
// ran it and then answered nobody for seconds); the id lets the client look before it
// sends the job again (or it sends it again with the same Idempotency-Key).
class AdmissionUnsettled : public QueueUnavailable {
 public:
  AdmissionUnsettled(const std::string& what, std::string id)
      : QueueUnavailable(what), job_id(std::move(id)) {}
  std::string job_id;
};

class JobQueue {
 public:
  virtual ~JobQueue() = default;

  enum class Admission {
    kAccepted,
    kReplayed,  // the tenant's Idempotency-Key named a job already kept: `job` is that one
    kQueueFull,
    kTenantQueueFull,
    kShuttingDown,
    kTooLarge,     // the prepared job is larger than the backend can ever store (413)
    kStorageFull,  // the backend is out of memory (Redis OOM): retrying does not help (507)
  };
  // Queues a job for `spec`; `job` is set when accepted or replayed. Throws
  // QueueUnavailable only when the job was not stored (a 503 means "send it again"), and
  // AdmissionUnsettled when that cannot be known.
  virtual Admission submit(std::unique_ptr<JobSpec> spec, std::shared_ptr<Job>& job) = 0;

  // The job `tenant`'s Idempotency-Key `key` made, while it is kept; nullptr otherwise.
  // Asked before a retried submission's body is read: the retry costs a lookup.
  virtual std::shared_ptr<Job> replay(const std::string& tenant, const std::string& key) = 0;

  struct Lookup {
    std::shared_ptr<Job> job;
    bool evicted = false;  // known, but its results were dropped (TTL or memory cap)
  };
  virtual Lookup find(const std::string& id) = 0;
  // Waits up to `seconds` for `job` to end, and returns it as it stands then.
  virtual std::shared_ptr<Job> wait(const std::shared_ptr<Job>& job, double seconds) = 0;
  virtual size_t queue_position(const Job& job) = 0;  // 1 = next to run; 0 = not queued
  // One artifact of a finished job, bytes included; nullopt when it has none by that name.
  virtual std::optional<Artifact> artifact(const Job& job, const std::string& name) = 0;
  // The .gltf view (glb_to_gltf) of the finished job's .glb artifact `glb_name`: built
  // on its first request, once however many ask at a time, then the same bytes for every
  // request. Null when the job has no such artifact or has not finished.
  virtual SharedBytes gltf_view(Job& job, const std::string& glb_name) = 0;

  // Cancels a queued job at once and asks a running one to stop (its worker ends it).
  // Returns false when the job has already finished.
  virtual bool cancel(const std::shared_ptr<Job>& job, const std::string& reason) = 0;
  // Forgets a finished job; false when it is still queued or running.
  virtual bool remove(const std::string& id) = 0;

  virtual bool accepting() const = 0;  // new submissions may come (ready)
  virtual size_t queued() = 0;         // cheap: for the 429 check before a body is parsed
  virtual void evict() = 0;            // drops finished jobs past the TTL or over the caps
  virtual StoreCounts counts() = 0;
};

// A new random job id (128 bits, hex): not guessable from another job's id.
std::string new_job_id();

}  // namespace spheremap::api
