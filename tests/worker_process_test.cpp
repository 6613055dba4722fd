// Worker processes (server/worker_process.h) with the real binary: a job whose worker
// died before it began (a child killed while idle, a replacement that could not start)
// runs on a fresh child instead of failing worker_crashed; a job that did begin and
// crashed is not run again.
#include "server/worker_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/map/pipeline.h"
#include "server/worker_protocol.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using server::JobStatus;
using server::WorkerLimits;
using server::WorkerProcess;

WorkerLimits limits_for(std::string executable) {
  WorkerLimits limits;
  limits.executable = std::move(executable);
  limits.max_artifact_bytes = size_t{1} << 30;
  return limits;
}

std::shared_ptr<server::Job> small_job() {
  auto job = std::make_shared<server::Job>();
  job->id = "test";
  job->spec = std::make_unique<server::JobSpec>();
  job->spec->input = testing::icosphere(1);
  job->spec->prepared = prepare_mesh(job->spec->input, {});
  return job;
}

std::string problem_of(const server::Job& job) {
  return job.error ? job.error->problem + ": " + job.error->detail : "";
}

// Waits until `pid` is no longer a running child of ours (a zombie counts as gone).
void wait_until_dead(pid_t pid) {
  for (int i = 0; i < 200; ++i) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(stat, line);
    if (line.empty() || line.find(") Z") != std::string::npos) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  FAIL() << "process " << pid << " still runs";
}

// As `spheremap serve` does (serve.cpp, and Service's constructor): writing a request to a
// child that died is EPIPE, not the end of the process. For every test of this file: CTest
// runs each alone, and a test that writes to a worker that never starts died of SIGPIPE.
const bool kSigpipeIgnored = [] {
  signal(SIGPIPE, SIG_IGN);
  return true;
}();

TEST(WorkerProcess, AnIdleWorkerKilledBeforeTheJobIsReplaced) {
  ASSERT_TRUE(kSigpipeIgnored);
  WorkerProcess worker(limits_for(SPHEREMAP_BINARY));
  const pid_t idle = worker.pid();
  ASSERT_GT(idle, 0);
  ASSERT_EQ(kill(idle, SIGKILL), 0);
  wait_until_dead(idle);
  auto job = small_job();
  EXPECT_EQ(worker.run(*job, {}), JobStatus::kSucceeded) << problem_of(*job);
  EXPECT_FALSE(job->error) << problem_of(*job);
  EXPECT_FALSE(job->artifacts.empty());
  EXPECT_NE(worker.pid(), idle);
}

// The worker executable fails to start the first time (exit 127, as execv failing
// does), then works: the job runs on the second child.
TEST(WorkerProcess, AReplacementThatFailsToStartIsTriedOnceMore) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("spheremap-worker-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto script = dir / "worker.sh";
  {
    std::ofstream out(script);
    out << "#!/bin/sh\n"
        << "if [ ! -e '" << (dir / "started").string() << "' ]; then\n"
        << "  touch '" << (dir / "started").string() << "'; exit 127\n"
        << "fi\n"
        << "exec '" << SPHEREMAP_BINARY << "' \"$@\"\n";
  }
  std::filesystem::permissions(script, std::filesystem::perms::owner_all);
  {
    WorkerProcess worker(limits_for(script.string()));
    auto job = small_job();
    EXPECT_EQ(worker.run(*job, {}), JobStatus::kSucceeded) << problem_of(*job);
    EXPECT_TRUE(std::filesystem::exists(dir / "started"));
  }
  std::filesystem::remove_all(dir);
}

// Never starting at all: two tries, then the job fails and says why.
TEST(WorkerProcess, AWorkerThatNeverStartsFailsTheJobAfterTwoTries) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("spheremap-worker-never-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto script = dir / "worker.sh";
  {
    std::ofstream out(script);
    out << "#!/bin/sh\necho x >> '" << (dir / "tries").string() << "'\nexit 127\n";
  }
  std::filesystem::permissions(script, std::filesystem::perms::owner_all);
  {
    WorkerProcess worker(limits_for(script.string()));
    auto job = small_job();
    EXPECT_EQ(worker.run(*job, {}), JobStatus::kFailed);
    ASSERT_TRUE(job->error);
    EXPECT_EQ(job->error->problem, "worker_crashed");
    EXPECT_NE(job->error->detail.find("could not be started"), std::string::npos)
        << job->error->detail;
  }
  // The warm child started with the worker, which was given the job, and one fresh one.
  std::ifstream tries(dir / "tries");
  int lines = 0;
  for (std::string line; std::getline(tries, line);) ++lines;
  EXPECT_EQ(lines, 2);
  std::filesystem::remove_all(dir);
}

// A job that began and whose worker then died is not run again: a worker that answers
// once and then crashes on the job (SIGSEGV from a script standing in for the engine).
TEST(WorkerProcess, AJobThatBeganAndCrashedIsNotRunAgain) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("spheremap-worker-crash-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto script = dir / "worker.sh";
  {
    // Reads the 8-byte length and some of the request, writes a byte (a frame begun),
    // then dies of SIGSEGV.
    std::ofstream out(script);
    out << "#!/bin/bash\necho x >> '" << (dir / "tries").string() << "'\n"
        << "head -c 8 > /dev/null\nprintf 'x'\nkill -SEGV $$\n";
  }
  std::filesystem::permissions(script, std::filesystem::perms::owner_all);
  {
    WorkerProcess worker(limits_for(script.string()));
    auto job = small_job();
    EXPECT_EQ(worker.run(*job, {}), JobStatus::kFailed);
    ASSERT_TRUE(job->error);
    EXPECT_EQ(job->error->problem, "worker_crashed");
    EXPECT_NE(job->error->detail.find("SIGSEGV"), std::string::npos) << job->error->detail;
  }
  std::ifstream tries(dir / "tries");
  int lines = 0;
  for (std::string line; std::getline(tries, line);) ++lines;
  EXPECT_EQ(lines, 1);  // the warm child, which took the job; no second try
  std::filesystem::remove_all(dir);
}

// The watchdog kills a worker still busy past the time limit and says how long past,
// truly (it said "10 s past" of a kill 30 s past a 10 s limit). A script stands in for a
// stuck engine: it answers once (the job began), then sleeps.
TEST(WorkerProcess, TheWatchdogSaysHowLongPastTheLimitItWaited) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("spheremap-worker-stuck-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto script = dir / "worker.sh";
  std::ofstream(script) << "#!/bin/sh\nhead -c 8 > /dev/null\nprintf x\nexec sleep 30\n";
  std::filesystem::permissions(script, std::filesystem::perms::owner_all);
  {
    WorkerLimits limits = limits_for(script.string());
    limits.min_overrun_seconds = 0.6;
    WorkerProcess worker(limits);
    auto job = small_job();
    server::RunLimits run;
    run.time_limit_seconds = 0.3;
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(worker.run(*job, run), JobStatus::kFailed);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GE(waited, 0.9);
    EXPECT_LT(waited, 5.0);
    ASSERT_TRUE(job->error);
    EXPECT_EQ(job->error->problem, "time_limit");
    EXPECT_NE(job->error->detail.find("still busy 0.6 s past the time limit of 0.3 s"),
              std::string::npos)
        << job->error->detail;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace spheremap

namespace spheremap::server {
namespace {

// Progress crosses the worker pipe and Redis as JSON: every field comes back, the part too.
TEST(WorkerProtocol, ProgressRoundTripsWithThePart) {
  JobProgress p;
  p.stage = "optimize";
  p.level = 3;
  p.levels = 7;
  p.vertices = 1234;
  p.iteration = 56;
  p.folds = 2;
  p.energy = 1.25;
  p.part = 2;
  p.parts = 5;
  const JobProgress back = progress_from_json(progress_json(p));
  EXPECT_EQ(back.stage, "optimize");
  EXPECT_EQ(back.level, 3);
  EXPECT_EQ(back.levels, 7);
  EXPECT_EQ(back.vertices, 1234u);
  EXPECT_EQ(back.iteration, 56u);
  EXPECT_EQ(back.folds, 2u);
  EXPECT_EQ(back.energy, 1.25);
  EXPECT_EQ(back.part, 2u);
  EXPECT_EQ(back.parts, 5u);
  // A progress written before parts existed (a Redis hash of an older node) reads as one mesh.
  EXPECT_EQ(progress_from_json(R"({"stage":"hierarchy"})").parts, 0u);
}

}  // namespace
}  // namespace spheremap::server
