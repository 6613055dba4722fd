// StopCheck for parallel loops: an exception cannot leave an OpenMP loop, so each
// iteration asks skip(i) (which asks `should_stop` every `every` iterations, from any
// thread) and returns at once once a stop was seen; after the loop, throw_if_stopped()
// throws the InputError("stopped") StopCheck would have.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>

#include "core/mesh/input_error.h"

namespace spheremap {

class ParallelStop {
 public:
  // `should_stop` (may be null or empty: never stop) must outlive this, and be safe to
  // call from several threads at once.
  ParallelStop(const std::function<bool()>* should_stop, size_t every)
      : should_stop_(should_stop && *should_stop ? should_stop : nullptr), every_(every) {}

  bool skip(size_t i) {
    if (!should_stop_) return false;
    if (stopped_.load(std::memory_order_relaxed)) return true;
    if (i % every_ == 0 && (*should_stop_)()) stopped_ = true;
    return stopped_.load(std::memory_order_relaxed);
  }

  void throw_if_stopped() const {
    if (stopped_)
      throw InputError("stopped",
                       "stopped before the end: its deadline passed or it was cancelled");
  }

 private:
  const std::function<bool()>* should_stop_;
  size_t every_;
  std::atomic<bool> stopped_ = false;
};

}  // namespace spheremap
