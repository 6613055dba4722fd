// Intake (api/intake.h): submitted meshes are read on a few threads of its own, never more
// at once, and under a deadline that answers 503 rather than letting a request wait or
// work without end.
#include "api/intake.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "api/problem.h"

namespace spheremap {
namespace {

using api::Intake;
using api::IntakeDeadline;
using api::Problem;

std::string slug_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const Problem& p) {
    return std::to_string(p.status) + " " + p.slug;
  }
  return "no problem";
}

TEST(Intake, RunsTheWorkElsewhereAndPassesItsErrorsOn) {
  Intake intake(2, 10);
  std::thread::id ran_on;
  intake.run([&](const IntakeDeadline&) { ran_on = std::this_thread::get_id(); });
  EXPECT_NE(ran_on, std::this_thread::get_id());
  EXPECT_EQ(slug_of([&] {
              intake.run([](const IntakeDeadline&) { throw Problem(422, "x", "X", "bad"); });
            }),
            "422 x");
}

TEST(Intake, NeverReadsMoreThanItsThreadsAtOnce) {
  Intake intake(2, 30);
  std::atomic<int> now{0}, most{0};
  std::vector<std::thread> clients;
  for (int k = 0; k < 8; ++k)
    clients.emplace_back([&] {
      intake.run([&](const IntakeDeadline&) {
        const int running = ++now;
        for (int seen = most; running > seen && !most.compare_exchange_weak(seen, running);) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        --now;
      });
    });
  for (auto& c : clients) c.join();
  EXPECT_EQ(most, 2);
}

TEST(Intake, ARequestThatFindsNoThreadInTimeIsTurnedAwayAndNeverRuns) {
  Intake intake(1, 0.2);
  std::atomic<bool> release{false};
  std::thread hog([&] {
    intake.run([&](const IntakeDeadline&) {
      while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    });
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  bool ran = false;
  EXPECT_EQ(slug_of([&] { intake.run([&](const IntakeDeadline&) { ran = true; }); }),
            "503 intake_busy");
  release = true;
  hog.join();
  intake.run([](const IntakeDeadline&) {});  // the abandoned task is skipped, not run
  EXPECT_FALSE(ran);
}

TEST(Intake, WorkPastTheDeadlineStopsAtItsNextStage) {
  Intake intake(1, 0.1);
  EXPECT_EQ(slug_of([&] {
              intake.run([](const IntakeDeadline& deadline) {
                deadline.check("nothing");
                std::this_thread::sleep_for(std::chrono::milliseconds(200));
                deadline.check("a slow stage");
              });
            }),
            "503 intake_timeout");
}

// SIGTERM: a reader under way sees its deadline as passed (the glTF reader and the weld
// ask every few thousand elements), so no reader holds the process, whatever its timeout.
TEST(Intake, StopReadingEndsWorkUnderWayAsShuttingDown) {
  Intake intake(1, 3600);
  std::atomic<bool> started{false};
  std::thread stopper([&] {
    while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    intake.stop_reading();
  });
  EXPECT_EQ(slug_of([&] {
              intake.run([&](const IntakeDeadline& deadline) {
                started = true;
                while (!deadline.passed())  // as the readers' should_stop asks
                  std::this_thread::sleep_for(std::chrono::milliseconds(1));
                deadline.check("a test stage");
              });
            }),
            "503 shutting_down");
  stopper.join();
}

}  // namespace
}  // namespace spheremap
