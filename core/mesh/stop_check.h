// Lets long loops over untrusted input be stopped from outside (an intake deadline, a
// shutdown) without core knowing why. The work calls tick() per element; every
// kInterval elements it asks `should_stop`, and when that says true, tick() throws
// InputError("stopped"). A reader at the size caps then stops within milliseconds of
// being asked, instead of at the end of its stage.
#pragma once

#include <cstddef>
#include <functional>

#include "core/mesh/input_error.h"

namespace spheremap {

class StopCheck {
 public:
  // Elements between two questions: ~1 ms of the slowest loop, negligible overhead.
  static constexpr size_t kInterval = size_t{1} << 15;

  // `should_stop` (may be null or empty: never stop) must outlive this.
  explicit StopCheck(const std::function<bool()>* should_stop)
      : should_stop_(should_stop && *should_stop ? should_stop : nullptr) {}

  void tick(size_t elements = 1) {
    if (!should_stop_) return;
    pending_ += elements;
    if (pending_ < kInterval) return;
    pending_ = 0;
    check();
  }

  // The question itself (null: never stop), for a parallel loop's ParallelStop.
  const std::function<bool()>* should_stop() const { return should_stop_; }

  // Asks now, whatever the count.
  void check() const {
    if (should_stop_ && (*should_stop_)())
      throw InputError("stopped",
                       "reading stopped before the end: its deadline passed or the process is "
                       "shutting down");
  }

 private:
  const std::function<bool()>* should_stop_;
  size_t pending_ = 0;
};

}  // namespace spheremap
