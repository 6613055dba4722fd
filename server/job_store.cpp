#include "server/job_store.h"

#include <algorithm>
#include <cstdio>

#include "core/io/glb_writer.h"

namespace spheremap::server {
namespace {

// Remembered evicted ids, so that GET answers 410 rather than 404 for a while.
constexpr size_t kEvictedIdsKept = 100000;

// Ends a job that never ran or has stopped (caller holds the store's lock).
void mark_terminal(Job& job, JobStatus status) {
  std::lock_guard lock(job.mutex);
  job.status = status;
  job.finished = Clock::now();
  job.progress.stage = std::string(to_string(status));
  job.spec.reset();  // the input mesh is not needed any more
}

}  // namespace

JobStore::JobStore(StoreLimits limits, Observer observer)
    : limits_(limits), observer_(std::move(observer)) {}

JobStore::Admission JobStore::submit(std::unique_ptr<JobSpec> spec, std::shared_ptr<Job>& job) {
  {
    std::lock_guard lock(mutex_);
    if (!accepting_) return Admission::kShuttingDown;
    if (!spec->idempotency_key.empty()) {
      // Before the capacity checks: a retry of a job already queued takes no new slot.
      if ((job = replay_locked(spec->tenant, spec->idempotency_key))) return Admission::kReplayed;
    }
    if (queue_.size() >= limits_.queue_capacity) return Admission::kQueueFull;
    Tenant& tenant = tenants_[spec->tenant];
    if (tenant.queued >= limits_.tenant_max_queued) return Admission::kTenantQueueFull;
    ++tenant.queued;
    job = std::make_shared<Job>();
    job->tenant = spec->tenant;
    do job->id = new_job_id();
    while (jobs_.count(job->id));
    job->input_vertices = spec->input.vertex_count();
    job->input_faces = spec->input.face_count();
    job->input_bytes = spec->input_bytes;
    job->input_format = spec->input_format;
    job->options = spec->options_echo;
    job->spec = std::move(spec);
    jobs_[job->id] = job;
    if (!job->spec->idempotency_key.empty()) {
      std::pair<std::string, std::string> key{job->tenant, job->spec->idempotency_key};
      idempotent_[key] = job->id;
      idempotency_key_of_[job->id] = std::move(key);
    }
    queue_.push_back(job);
    // Told while no worker can take the job yet (next() needs mutex_), so its "queued"
    // line is logged before its "running" one. Order: mutex_, then the job's mutex.
    if (observer_) observer_(job, JobStatus::kQueued);
  }
  queue_cv_.notify_one();
  return Admission::kAccepted;
}

std::deque<std::shared_ptr<Job>>::iterator JobStore::pick_locked() {
  auto best = queue_.end();
  const Tenant* best_tenant = nullptr;
  std::unordered_set<std::string> seen;  // a tenant's oldest queued job stands for it
  for (auto it = queue_.begin(); it != queue_.end(); ++it) {
    if (!seen.insert((*it)->tenant).second) continue;
    const Tenant& t = tenants_[(*it)->tenant];
    if (limits_.tenant_max_running > 0 && t.running >= limits_.tenant_max_running) continue;
    if (!best_tenant || t.running < best_tenant->running ||
        (t.running == best_tenant->running && t.last_start < best_tenant->last_start))
      best = it, best_tenant = &t;
  }
  return best;
}

std::shared_ptr<Job> JobStore::next() {
  std::shared_ptr<Job> job;
  {
    std::unique_lock lock(mutex_);
    auto picked = queue_.end();
    queue_cv_.wait(lock, [&] { return closed_ || (picked = pick_locked()) != queue_.end(); });
    if (closed_) return nullptr;
    job = *picked;
    queue_.erase(picked);
    ++running_;
    Tenant& tenant = tenants_[job->tenant];
    --tenant.queued;
    ++tenant.running;
    tenant.last_start = Clock::now();
    {
      std::lock_guard job_lock(job->mutex);
      job->status = JobStatus::kRunning;
      job->started = Clock::now();
      job->progress.stage = "starting";
    }
    // Under mutex_ as well: a job's lines come in the order of its states.
    if (observer_) observer_(job, JobStatus::kRunning);
  }
  return job;
}

void JobStore::finish(const std::shared_ptr<Job>& job, JobStatus status) {
  std::vector<std::shared_ptr<Job>> evicted;
  {
    std::lock_guard lock(mutex_);
    --running_;
    mark_terminal(*job, status);
    Tenant& tenant = tenants_[job->tenant];
    --tenant.running;
    {
      std::lock_guard job_lock(job->mutex);
      result_bytes_ += job->artifact_bytes();
      tenant.result_bytes += job->artifact_bytes();
    }
    finished_.push_back(job);
    evict_locked(evicted);
  }
  queue_cv_.notify_all();  // a tenant at its running cap may go on
  job->finished_cv.notify_all();
  idle_cv_.notify_all();
  if (observer_) observer_(job, status);
}

std::shared_ptr<Job> JobStore::replay_locked(const std::string& tenant, const std::string& key) {
  const auto it = idempotent_.find({tenant, key});
  if (it == idempotent_.end()) return nullptr;
  const auto job = jobs_.find(it->second);
  return job == jobs_.end() ? nullptr : job->second;
}

std::shared_ptr<Job> JobStore::replay(const std::string& tenant, const std::string& key) {
  std::lock_guard lock(mutex_);
  return replay_locked(tenant, key);
}

void JobStore::forget_idempotency_key(const std::string& id) {
  const auto it = idempotency_key_of_.find(id);
  if (it == idempotency_key_of_.end()) return;
  idempotent_.erase(it->second);
  idempotency_key_of_.erase(it);
}

JobStore::Lookup JobStore::find(const std::string& id) {
  evict();
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it != jobs_.end()) return {it->second, false};
  return {nullptr, evicted_.count(id) > 0};
}

std::shared_ptr<Job> JobStore::wait(const std::shared_ptr<Job>& job, double seconds) {
  std::unique_lock lock(job->mutex);
  job->finished_cv.wait_for(lock, std::chrono::duration<double>(seconds),
                            [&] { return is_terminal(job->status); });
  return job;
}

std::optional<Artifact> JobStore::artifact(const Job& job, const std::string& name) {
  std::lock_guard lock(job.mutex);
  for (const Artifact& a : job.artifacts)
    if (a.name == name) return a;
  return std::nullopt;
}

SharedBytes JobStore::gltf_view(Job& job, const std::string& glb_name) {
  SharedBytes glb;
  auto built = [&]() -> SharedBytes {  // caller holds job.mutex
    const auto view = job.gltf_views.find(glb_name);
    return view == job.gltf_views.end() ? nullptr : view->second;
  };
  {
    std::lock_guard lock(job.mutex);
    if (SharedBytes view = built()) return view;
    // Finished jobs only: a running job's artifacts may still be dropped (cancel, failure).
    if (!is_terminal(job.status)) return nullptr;
    for (const Artifact& a : job.artifacts)
      if (a.name == glb_name) glb = a.bytes;
  }
  if (!glb) return nullptr;
  // Concurrent first requests wait here for the one conversion rather than make their own.
  std::lock_guard building(job.gltf_building);
  {
    std::lock_guard lock(job.mutex);
    if (SharedBytes view = built()) return view;
  }
  SharedBytes view = share_bytes(glb_to_gltf(*glb));  // outside every lock: it takes a while
  std::vector<std::shared_ptr<Job>> evicted;
  std::lock_guard lock(mutex_);
  {
    std::lock_guard job_lock(job.mutex);
    job.gltf_views[glb_name] = view;
    // finish() counted the job's bytes; the view joins them while the job is kept (an
    // evicted job's view goes with the last request that holds it).
    const auto kept = jobs_.find(job.id);
    if (kept != jobs_.end() && kept->second.get() == &job) {
      result_bytes_ += view->size();
      tenants_[job.tenant].result_bytes += view->size();
    }
  }
  evict_locked(evicted);  // the view may take the results over their caps
  return view;
}

size_t JobStore::queue_position(const Job& job) {
  std::lock_guard lock(mutex_);
  for (size_t i = 0; i < queue_.size(); ++i)
    if (queue_[i].get() == &job) return i + 1;
  return 0;
}

bool JobStore::cancel(const std::shared_ptr<Job>& job, const std::string& reason) {
  bool was_queued = false;
  {
    std::lock_guard lock(mutex_);
    const auto queued = std::find(queue_.begin(), queue_.end(), job);
    if (queued != queue_.end()) {
      queue_.erase(queued);
      --tenants_[job->tenant].queued;
      {
        std::lock_guard job_lock(job->mutex);
        job->cancel_reason = reason;
      }
      mark_terminal(*job, JobStatus::kCancelled);
      finished_.push_back(job);
      was_queued = true;
    } else {
      std::lock_guard job_lock(job->mutex);
      if (job->status != JobStatus::kRunning) return false;
      if (job->cancel_reason.empty()) job->cancel_reason = reason;
      job->cancel = true;  // the engine polls it; the worker ends the job
    }
  }
  if (was_queued) {
    job->finished_cv.notify_all();
    idle_cv_.notify_all();
    if (observer_) observer_(job, JobStatus::kCancelled);
  }
  return true;
}

bool JobStore::remove(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return false;
  std::shared_ptr<Job> job = it->second;
  {
    std::lock_guard job_lock(job->mutex);
    if (!is_terminal(job->status)) return false;
    result_bytes_ -= job->artifact_bytes();
    tenants_[job->tenant].result_bytes -= job->artifact_bytes();
  }
  jobs_.erase(it);
  forget_idempotency_key(id);
  finished_.erase(std::remove(finished_.begin(), finished_.end(), job), finished_.end());
  return true;
}

void JobStore::stop_accepting() {
  std::lock_guard lock(mutex_);
  accepting_ = false;
}

bool JobStore::accepting() const {
  std::lock_guard lock(mutex_);
  return accepting_;
}

void JobStore::cancel_all(const std::string& reason) {
  std::vector<std::shared_ptr<Job>> active;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, job] : jobs_) active.push_back(job);
  }
  for (const auto& job : active) cancel(job, reason);
}

bool JobStore::wait_idle(Clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  return idle_cv_.wait_until(lock, deadline, [&] { return queue_.empty() && running_ == 0; });
}

void JobStore::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  queue_cv_.notify_all();
}

size_t JobStore::queued() {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

void JobStore::evict() {
  std::vector<std::shared_ptr<Job>> evicted;
  std::lock_guard lock(mutex_);
  evict_locked(evicted);
}

void JobStore::evict_job_locked(std::deque<std::shared_ptr<Job>>::iterator at,
                                std::vector<std::shared_ptr<Job>>& evicted) {
  const std::shared_ptr<Job> job = *at;
  size_t bytes;
  {
    std::lock_guard job_lock(job->mutex);
    bytes = job->artifact_bytes();
  }
  result_bytes_ -= bytes;
  tenants_[job->tenant].result_bytes -= bytes;
  jobs_.erase(job->id);
  forget_idempotency_key(job->id);
  remember_evicted(job->id);
  ++evicted_total_;
  evicted.push_back(job);  // freed outside the lock
  finished_.erase(at);
}

void JobStore::evict_locked(std::vector<std::shared_ptr<Job>>& evicted) {
  const auto now = Clock::now();
  const auto ttl = std::chrono::duration<double>(limits_.result_ttl_seconds);
  // A tenant over its own share loses its own oldest results first. The scan of the
  // finished jobs runs only then: eviction runs on every lookup.
  const bool over_share = std::any_of(tenants_.begin(), tenants_.end(), [&](const auto& t) {
    return t.second.result_bytes > limits_.tenant_result_memory_bytes;
  });
  for (auto it = finished_.begin(); over_share && it != finished_.end();) {
    if (tenants_[(*it)->tenant].result_bytes > limits_.tenant_result_memory_bytes) {
      const auto offset = it - finished_.begin();
      evict_job_locked(it, evicted);
      it = finished_.begin() + offset;
    } else {
      ++it;
    }
  }
  while (!finished_.empty()) {
    const std::shared_ptr<Job>& oldest = finished_.front();
    bool expired;
    {
      std::lock_guard job_lock(oldest->mutex);
      expired = now - *oldest->finished > ttl;
    }
    if (!expired && result_bytes_ <= limits_.result_memory_bytes &&
        finished_.size() <= limits_.max_jobs_kept)
      break;
    evict_job_locked(finished_.begin(), evicted);
  }
  // Tenants with nothing left are forgotten (a client address is not kept forever).
  for (auto it = tenants_.begin(); it != tenants_.end();)
    it = it->second.queued == 0 && it->second.running == 0 && it->second.result_bytes == 0
             ? tenants_.erase(it)
             : std::next(it);
}

void JobStore::remember_evicted(const std::string& id) {
  evicted_.insert(id);
  evicted_order_.push_back(id);
  if (evicted_order_.size() > kEvictedIdsKept) {
    evicted_.erase(evicted_order_.front());
    evicted_order_.pop_front();
  }
}

StoreCounts JobStore::counts() {
  std::lock_guard lock(mutex_);
  StoreCounts c;
  c.queued = queue_.size();
  c.running = running_;
  c.result_bytes = result_bytes_;
  c.evicted = evicted_total_;
  for (const auto& job : finished_) {
    std::lock_guard job_lock(job->mutex);
    if (job->status == JobStatus::kSucceeded) ++c.succeeded;
    if (job->status == JobStatus::kFailed) ++c.failed;
    if (job->status == JobStatus::kCancelled) ++c.cancelled;
  }
  return c;
}

}  // namespace spheremap::server
