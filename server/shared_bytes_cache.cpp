#include "server/shared_bytes_cache.h"

namespace spheremap::server {

SharedBytes SharedBytesCache::get(const std::string& key,
                                  const std::function<SharedBytes()>& load) {
  std::promise<SharedBytes> promise;
  std::shared_future<SharedBytes> value;
  bool loader = false;
  {
    std::lock_guard lock(mutex_);
    if (auto it = entries_.find(key); it != entries_.end()) {
      ages_.splice(ages_.begin(), ages_, it->second.age);
      value = it->second.value;
    } else {
      value = promise.get_future().share();
      ages_.push_front(key);
      entries_.emplace(key, Entry{value, 0, ages_.begin()});
      loader = true;
    }
  }
  if (!loader) return value.get();  // outside the lock: a load may take a while
  SharedBytes bytes;
  try {
    bytes = load();
  } catch (...) {
    promise.set_exception(std::current_exception());
    std::lock_guard lock(mutex_);
    if (auto it = entries_.find(key); it != entries_.end()) erase_locked(it);
    throw;
  }
  promise.set_value(bytes);
  std::lock_guard lock(mutex_);
  const auto it = entries_.find(key);
  if (it == entries_.end()) return bytes;
  if (!bytes || bytes->size() > capacity_) {
    erase_locked(it);
    return bytes;
  }
  it->second.size = bytes->size();
  kept_ += bytes->size();
  while (kept_ > capacity_) erase_locked(entries_.find(ages_.back()));
  return bytes;
}

void SharedBytesCache::erase_locked(std::unordered_map<std::string, Entry>::iterator it) {
  kept_ -= it->second.size;
  ages_.erase(it->second.age);
  entries_.erase(it);
}

size_t SharedBytesCache::kept_bytes() const {
  std::lock_guard lock(mutex_);
  return kept_;
}

}  // namespace spheremap::server
