#include "api/intake.h"

#include <algorithm>
#include <future>
#include <sstream>

#include "api/problem.h"

namespace spheremap::api {
namespace {

std::string seconds_text(double seconds) {
  std::ostringstream text;
  text << seconds << " s";
  return text.str();
}

}  // namespace

void IntakeDeadline::check(const char* stage) const {
  if (!passed()) return;
  if (stopping_ && stopping_->load())
    throw Problem(
        503, "shutting_down", "Shutting down",
        std::string("the server is shutting down; it stopped reading this mesh after ") + stage);
  throw Problem(503, "intake_timeout", "Mesh preparation too slow",
                std::string("reading and checking the mesh took longer than "
                            "intake_timeout_seconds (") +
                    seconds_text(seconds_) + "), stopped after " + stage +
                    "; the server is busy or the mesh is near the size caps: retry later");
}

// One request's work. `state` moves queued -> running (an intake thread took it) or
// queued -> abandoned (its deadline passed first); whoever moves it first decides.
struct Intake::Task {
  enum class State { kQueued, kRunning, kAbandoned };
  Task(const std::function<void(const IntakeDeadline&)>* work, IntakeDeadline deadline)
      : work(work), deadline(deadline) {}
  const std::function<void(const IntakeDeadline&)>* work;
  IntakeDeadline deadline;
  State state = State::kQueued;
  std::promise<void> done;
};

Intake::Intake(size_t threads, double timeout_seconds) : timeout_seconds_(timeout_seconds) {
  for (size_t k = 0; k < std::max<size_t>(threads, 1); ++k)
    threads_.emplace_back([this] { serve(); });
}

Intake::~Intake() {
  stop_reading_ = true;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void Intake::serve() {
  for (;;) {
    std::shared_ptr<Task> task;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
      if (stopping_ && tasks_.empty()) return;
      task = std::move(tasks_.front());
      tasks_.pop_front();
      if (task->state == Task::State::kAbandoned) continue;
      task->state = Task::State::kRunning;
    }
    try {
      (*task->work)(task->deadline);
      task->done.set_value();
    } catch (...) {
      task->done.set_exception(std::current_exception());
    }
  }
}

void Intake::run(const std::function<void(const IntakeDeadline&)>& work) {
  const auto timeout = std::chrono::duration_cast<IntakeDeadline::Clock::duration>(
      std::chrono::duration<double>(timeout_seconds_));
  auto task = std::make_shared<Task>(&work, IntakeDeadline(IntakeDeadline::Clock::now() + timeout,
                                                           timeout_seconds_, &stop_reading_));
  std::future<void> done = task->done.get_future();
  {
    std::lock_guard lock(mutex_);
    tasks_.push_back(task);
  }
  wake_.notify_one();
  if (done.wait_until(task->deadline.at()) != std::future_status::ready) {
    std::unique_lock lock(mutex_);
    if (task->state == Task::State::kQueued) {
      task->state = Task::State::kAbandoned;  // the thread that pops it skips it
      throw Problem(503, "intake_busy", "Server busy",
                    "no intake thread was free within intake_timeout_seconds (" +
                        seconds_text(timeout_seconds_) +
                        "): every one is reading other "
                        "meshes; retry later");
    }
    // Running: it sees the deadline within milliseconds (the readers ask as they go);
    // `work` (and the request it reads) must outlive it, so wait.
  }
  done.get();
}

}  // namespace spheremap::api
