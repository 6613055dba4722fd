// The memory this node's running jobs may use together (setting jobs_memory_bytes). Each
// job is charged its estimated peak (job_memory.h) before it starts and gives it back when
// it ends; a job that does not fit waits, in order of arrival, so a large job is not
// overtaken for ever by small ones. A job estimated above the whole budget is charged the
// whole budget: it runs, alone.
//
// Why, beside each worker process's RLIMIT_AS (worker_memory_bytes): that cap stops one
// job that runs away, but with several workers their caps together exceed the machine
// (the default cap is 3/4 of it, per worker), so four large jobs at once could still
// push the node into swap or the OOM killer, which picks a process we do not choose. The
// budget keeps the sum of what is expected under one figure; the cap stays the backstop
// for a job whose estimate was wrong.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <list>
#include <mutex>
#include <optional>

namespace spheremap::server {

class MemoryBudget {
 public:
  explicit MemoryBudget(size_t bytes) : total_(bytes) {}

  // Bytes held by one running job; given back when destroyed.
  class Charge {
   public:
    Charge(MemoryBudget* budget, size_t bytes) : budget_(budget), bytes_(bytes) {}
    Charge(Charge&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) {
      other.budget_ = nullptr;
    }
    Charge(const Charge&) = delete;
    Charge& operator=(const Charge&) = delete;
    Charge& operator=(Charge&&) = delete;
    ~Charge() {
      if (budget_) budget_->release(bytes_);
    }
    size_t bytes() const { return bytes_; }

   private:
    MemoryBudget* budget_;
    size_t bytes_;
  };

  // Waits until `bytes` (at most the whole budget) fit and every earlier waiter has been
  // served; nullopt if `give_up()` (asked every 100 ms: a cancel, a stop) turns true first.
  std::optional<Charge> acquire(size_t bytes, const std::function<bool()>& give_up);

  size_t total() const { return total_; }
  size_t in_use() const;

 private:
  void release(size_t bytes);

  const size_t total_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  size_t used_ = 0;
  std::list<size_t> waiting_;  // one entry per waiter, in order of arrival
};

}  // namespace spheremap::server
