// Intake: where a submitted mesh is read and checked (glTF parse, decode, weld, topology)
// before it becomes a job. It runs on threads of its own, a few of them, never on the
// HTTP threads, and under a deadline:
//
// - A mesh at the size caps costs seconds of CPU and about 8x its bytes of memory
//   (measured: a 23.6 MB GLB of 1.3M triangles, 2.0 s and 190 MB). Read on every HTTP
//   thread at once, 16 of them would ask for 16 cores and 3 GB; here at most `threads`
//   meshes are read at a time, so intake's CPU and memory are bounded whatever the
//   number of connections, and the HTTP threads only wait.
// - The deadline (from the moment the request reaches intake) covers the wait for an
//   intake thread and the work: a request still waiting when it passes is answered 503
//   intake_busy; work that outlasts it stops with 503 intake_timeout: the glTF reader
//   and the weld ask IntakeDeadline::passed() every few thousand elements, so an intake
//   thread is free again within milliseconds of the deadline, and stop_reading() (on
//   SIGTERM) ends them the same way (503 shutting_down).
// - Envelopes (prepare wrap, auto: seconds and hundreds of MB) are not built here: their
//   grid is laid out and checked, and the job's worker builds them under the job's time
//   limit and memory charge (job_request.cpp, PrepareOptions::defer_envelopes).
//
// The HTTP thread waits for the answer because the API answers a bad mesh at once (400,
// 413, 422) rather than as a failed job later; it holds the request, whose bytes the
// intake thread reads in place (no copy of the body).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace spheremap::api {

// When a preparation must be done by; `check` throws Problem 503 intake_timeout after it,
// or 503 shutting_down once the intake is told to stop (`stopping`, may be null).
class IntakeDeadline {
 public:
  using Clock = std::chrono::steady_clock;
  IntakeDeadline(Clock::time_point at, double seconds, const std::atomic<bool>* stopping = nullptr)
      : at_(at), seconds_(seconds), stopping_(stopping) {}
  // Cheap enough to ask every few thousand elements (the readers do).
  bool passed() const { return (stopping_ && stopping_->load()) || Clock::now() >= at_; }
  Clock::time_point at() const { return at_; }
  // `stage`: what was just done, for the problem's detail.
  void check(const char* stage) const;

 private:
  Clock::time_point at_;
  double seconds_;
  const std::atomic<bool>* stopping_;
};

class Intake {
 public:
  // `threads` at least 1; `timeout_seconds` the deadline of each request.
  Intake(size_t threads, double timeout_seconds);
  ~Intake();
  Intake(const Intake&) = delete;
  Intake& operator=(const Intake&) = delete;

  // Runs `work` on an intake thread and returns when it has ended, rethrowing what it
  // threw. Throws Problem 503 intake_busy when no intake thread took it before the
  // deadline (it then never runs).
  void run(const std::function<void(const IntakeDeadline&)>& work);

  size_t threads() const { return threads_.size(); }

  // Shutdown: work under way sees its deadline as passed (the readers stop within
  // milliseconds), so that no reader holds the process after SIGTERM.
  void stop_reading() { stop_reading_ = true; }

 private:
  struct Task;
  void serve();

  double timeout_seconds_;
  std::atomic<bool> stop_reading_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Task>> tasks_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace spheremap::api
