// Parallel loops over index ranges. Every loop writes only its own element, so results
// are bit-identical for any thread count; small ranges run serially (no thread start-up).
#pragma once

#include <cstddef>
#include <cstdint>

namespace spheremap {

inline constexpr size_t kParallelThreshold = 8192;

// Number of threads for `threads` requested (0 = all cores).
int resolve_threads(int threads);

template <class Body>
void parallel_for(size_t count, int threads, Body&& body) {
  const long long n = static_cast<long long>(count);
#pragma omp parallel for schedule(static) num_threads(threads) if (count >= kParallelThreshold)
  for (long long i = 0; i < n; ++i) body(static_cast<size_t>(i));
}

// Sum of integer counts (exact, so any reduction order gives the same result).
template <class Count>
size_t parallel_count(size_t count, int threads, Count&& predicate) {
  const long long n = static_cast<long long>(count);
  size_t total = 0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : total) if (count >= kParallelThreshold)
  for (long long i = 0; i < n; ++i) total += predicate(static_cast<size_t>(i)) ? 1 : 0;
  return total;
}

}  // namespace spheremap
