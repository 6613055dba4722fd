// Bytes loaded once and shared: every request that asks for a key while it loads waits
// for that one load, and the result is kept a while (the least recently used go first,
// at most `capacity` bytes in all). Redis mode fetches artifacts and builds .gltf views
// through it, so 16 parallel downloads of one artifact make one fetch, not 16 copies.
#pragma once

#include <cstddef>
#include <functional>
#include <future>
#include <list>
#include <mutex>
#include <string>
#include <unordered_map>

#include "server/api_types.h"

namespace spheremap::server {

class SharedBytesCache {
 public:
  explicit SharedBytesCache(size_t capacity) : capacity_(capacity) {}

  // The bytes under `key`: kept, or loading for another request (waited for), or loaded
  // now by `load`. A null result or one over the capacity is shared but not kept; an
  // exception from `load` reaches every request that waited for it, and nothing is kept.
  SharedBytes get(const std::string& key, const std::function<SharedBytes()>& load);

  size_t kept_bytes() const;

 private:
  struct Entry {
    std::shared_future<SharedBytes> value;
    size_t size = 0;  // 0 while loading
    std::list<std::string>::iterator age;
  };
  void erase_locked(std::unordered_map<std::string, Entry>::iterator it);

  const size_t capacity_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Entry> entries_;
  std::list<std::string> ages_;  // most recently used first
  size_t kept_ = 0;
};

}  // namespace spheremap::server
