#include "api/service_metrics.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace spheremap::api {
namespace {

std::string format_number(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

void counter_family(const std::string& name, const std::string& help, const std::string& label,
                    const std::map<std::string, unsigned long long>& values, std::string& out) {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " counter\n";
  for (const auto& [key, value] : values)
    out += name + "{" + label + "=\"" + key + "\"} " + std::to_string(value) + "\n";
}

void gauge(const std::string& name, const std::string& help, double value, std::string& out) {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " gauge\n";
  out += name + " " + format_number(value) + "\n";
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
  size_t bucket = 0;
  while (bucket < bounds_.size() && value > bounds_[bucket]) ++bucket;
  ++counts_[bucket];
  sum_ += value;
  ++count_;
}

void Histogram::render(const std::string& name, const std::string& help, std::string& out) const {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " histogram\n";
  unsigned long long cumulative = 0;
  for (size_t i = 0; i < bounds_.size(); ++i) {
    cumulative += counts_[i];
    out += name + "_bucket{le=\"" + format_number(bounds_[i]) + "\"} " +
           std::to_string(cumulative) + "\n";
  }
  out += name + "_bucket{le=\"+Inf\"} " + std::to_string(count_) + "\n";
  out += name + "_sum " + format_number(sum_) + "\n";
  out += name + "_count " + std::to_string(count_) + "\n";
}

ServiceMetrics::ServiceMetrics()
    : run_seconds_({0.01, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 300}),
      wait_seconds_({0.01, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 300}),
      input_bytes_({1e4, 1e5, 1e6, 1e7, 1e8}),
      input_faces_({1e2, 1e3, 1e4, 1e5, 1e6, 1e7}) {
  for (const char* s : {"succeeded", "failed", "cancelled"}) ended_[s] = 0;
}

void ServiceMetrics::job_accepted(size_t input_bytes, size_t faces) {
  std::lock_guard lock(mutex_);
  input_bytes_.observe(static_cast<double>(input_bytes));
  input_faces_.observe(static_cast<double>(faces));
}

void ServiceMetrics::job_ended(JobStatus status, double run_seconds, double wait_seconds) {
  std::lock_guard lock(mutex_);
  ++ended_[std::string(to_string(status))];
  if (run_seconds > 0) run_seconds_.observe(run_seconds);
  wait_seconds_.observe(wait_seconds);
}

void ServiceMetrics::rejected(const std::string& reason) {
  std::lock_guard lock(mutex_);
  ++rejected_[reason];
}

void ServiceMetrics::request(int status) {
  std::lock_guard lock(mutex_);
  ++responses_[std::to_string(status)];
}

std::string ServiceMetrics::render(const StoreCounts& store, size_t queue_capacity,
                                   int workers) const {
  std::string out;
  out += "# HELP spheremap_jobs Jobs the service holds, by state.\n# TYPE spheremap_jobs gauge\n";
  const std::pair<const char*, size_t> states[] = {{"queued", store.queued},
                                                   {"running", store.running},
                                                   {"succeeded", store.succeeded},
                                                   {"failed", store.failed},
                                                   {"cancelled", store.cancelled}};
  for (const auto& [state, count] : states)
    out += std::string("spheremap_jobs{state=\"") + state + "\"} " + std::to_string(count) + "\n";
  gauge("spheremap_queue_depth", "Jobs waiting for a worker.", static_cast<double>(store.queued),
        out);
  gauge("spheremap_queue_capacity", "Jobs the queue holds at most.",
        static_cast<double>(queue_capacity), out);
  gauge("spheremap_workers", "Jobs mapped at once.", workers, out);
  gauge("spheremap_result_bytes", "Bytes of artifacts kept for finished jobs.",
        static_cast<double>(store.result_bytes), out);
  gauge("spheremap_resident_memory_bytes", "Resident memory of the process.",
        static_cast<double>(resident_memory_bytes()), out);
  std::lock_guard lock(mutex_);
  counter_family("spheremap_jobs_finished_total", "Jobs that reached a terminal state.", "status",
                 ended_, out);
  counter_family("spheremap_rejections_total", "Submissions refused, by reason.", "reason",
                 rejected_, out);
  counter_family("spheremap_http_responses_total", "HTTP responses, by status code.", "code",
                 responses_, out);
  counter_family("spheremap_jobs_evicted_total", "Finished jobs dropped (TTL or memory cap).",
                 "cause", {{"ttl_or_cap", store.evicted}}, out);
  run_seconds_.render("spheremap_job_run_seconds", "Time a job ran on a worker.", out);
  wait_seconds_.render("spheremap_job_wait_seconds", "Time a job waited in the queue.", out);
  input_bytes_.render("spheremap_input_bytes", "Size of accepted request bodies.", out);
  input_faces_.render("spheremap_input_faces", "Triangles of accepted meshes.", out);
  return out;
}

size_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  size_t pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return pages_resident * static_cast<size_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace spheremap::api
