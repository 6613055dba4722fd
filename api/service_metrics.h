// The service's counters and histograms, rendered in the Prometheus text format
// (version 0.0.4) for GET /metrics. Thread-safe.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "api/job_queue.h"

namespace spheremap::api {

class Histogram {
 public:
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
  // Appends the HELP and TYPE lines and the _bucket, _sum and _count lines of `name`.
  void render(const std::string& name, const std::string& help, std::string& out) const;

 private:
  std::vector<double> bounds_;
  std::vector<unsigned long long> counts_;  // per bucket, not cumulative
  double sum_ = 0;
  unsigned long long count_ = 0;
};

class ServiceMetrics {
 public:
  ServiceMetrics();
  void job_accepted(size_t input_bytes, size_t faces);
  void job_ended(JobStatus status, double run_seconds, double wait_seconds);
  void rejected(const std::string& reason);  // "queue_full", "too_large", "boundary", ...
  void request(int status);

  // The whole exposition: these plus the store's gauges and the process's memory.
  std::string render(const StoreCounts& store, size_t queue_capacity, int workers) const;

 private:
  mutable std::mutex mutex_;
  Histogram run_seconds_, wait_seconds_, input_bytes_, input_faces_;
  std::map<std::string, unsigned long long> ended_, rejected_, responses_;
};

// The process's resident memory (from /proc/self/statm), 0 when unknown.
size_t resident_memory_bytes();

}  // namespace spheremap::api
