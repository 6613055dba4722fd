#include "server/memory_budget.h"

#include <algorithm>
#include <chrono>

namespace spheremap::server {

std::optional<MemoryBudget::Charge> MemoryBudget::acquire(size_t bytes,
                                                          const std::function<bool()>& give_up) {
  bytes = std::min(bytes, total_);
  std::unique_lock lock(mutex_);
  const auto me = waiting_.insert(waiting_.end(), bytes);
  const auto my_turn = [&] { return waiting_.begin() == me && used_ + bytes <= total_; };
  while (!my_turn()) {
    lock.unlock();  // give_up may look at this budget (in_use) or take other locks
    const bool quit = give_up();
    lock.lock();
    if (quit) {
      waiting_.erase(me);
      changed_.notify_all();  // the next waiter may be first now
      return std::nullopt;
    }
    changed_.wait_for(lock, std::chrono::milliseconds(100), my_turn);
  }
  waiting_.erase(me);
  used_ += bytes;
  changed_.notify_all();
  return Charge(this, bytes);
}

size_t MemoryBudget::in_use() const {
  std::lock_guard lock(mutex_);
  return used_;
}

void MemoryBudget::release(size_t bytes) {
  {
    std::lock_guard lock(mutex_);
    used_ -= bytes;
  }
  changed_.notify_all();
}

}  // namespace spheremap::server
