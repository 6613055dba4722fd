// The Redis queue's scripts against a real redis-server (started here on a free loopback
// port, no persistence; the tests skip without redis-server): two queue objects stand for
// two replicas, and the workers' side is driven by hand, so that each race the scripts
// must settle (a reclaimed job finished twice, a cancel while queued, a poison job, the
// result cap) is played out exactly.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/job_view.h"
#include "core/io/glb_writer.h"
#include "core/map/pipeline.h"
#include "server/redis_queue.h"
#include "tests/mesh_generators.h"
#include "tests/test_server.h"

namespace spheremap {
namespace {

using server::JobQueue;
using server::RedisAddress;
using server::RedisConnection;
using server::RedisJobQueue;
using server::RedisQueueLimits;

int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t size = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  close(fd);
  return ntohs(address.sin_port);
}

// A redis-server of this test's own, flushed before each test.
class RedisQueueTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (std::system("command -v redis-server > /dev/null") != 0) return;
    port_ = free_port();
    dir_ = std::filesystem::temp_directory_path() / ("spheremap-redis-" + std::to_string(port_));
    std::filesystem::create_directories(dir_);
    const std::string command = "redis-server --port " + std::to_string(port_) +
                                " --bind 127.0.0.1 --save '' --appendonly no --daemonize yes" +
                                // DEBUG SLEEP plays a stalled Redis
                                " --enable-debug-command local" + " --dir " + dir_.string() +
                                " --pidfile " + (dir_ / "redis.pid").string() + " --logfile " +
                                (dir_ / "redis.log").string();
    if (std::system(command.c_str()) != 0) return;
    for (int i = 0; i < 100; ++i) {
      try {
        RedisConnection probe(address());
        probe.command({"PING"});
        started_ = true;
        return;
      } catch (const std::exception&) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
  }
  static void TearDownTestSuite() {
    if (!started_) return;
    try {
      RedisConnection(address()).command({"SHUTDOWN", "NOSAVE"});
    } catch (const std::exception&) {
      // SHUTDOWN closes the connection without an answer
    }
    std::filesystem::remove_all(dir_);
  }
  void SetUp() override {
    if (!started_) GTEST_SKIP() << "redis-server not available";
    RedisConnection(address()).command({"FLUSHALL"});
  }
  static RedisAddress address() {
    RedisAddress a;
    a.port = port_;
    return a;
  }
  static std::unique_ptr<server::JobSpec> spec(const std::string& tenant = "t",
                                               const std::string& idempotency_key = "",
                                               int subdivisions = 1) {
    auto s = std::make_unique<server::JobSpec>();
    s->input = testing::icosphere(subdivisions);
    s->prepared = prepare_mesh(s->input, {});
    s->tenant = tenant;
    s->idempotency_key = idempotency_key;
    return s;
  }
  static long long integer(const std::vector<std::string_view>& command) {
    return RedisConnection(address()).command(command).integer();
  }
  // Bytes Redis has read from its clients so far.
  static long long bytes_received() {
    const std::string info = RedisConnection(address()).command({"INFO", "stats"}).text();
    const size_t at = info.find("total_net_input_bytes:");
    return std::stoll(info.substr(at + 22));
  }
  // A worker's claim, retried until the entry is there (XREADGROUP blocks briefly).
  static RedisJobQueue::Delivery claim(RedisJobQueue& queue, RedisConnection& redis,
                                       const std::string& consumer) {
    for (int i = 0; i < 50; ++i)
      if (auto d = queue.claim(redis, consumer, 0.1)) return *d;
    throw std::runtime_error("nothing to claim");
  }
  // Submits a job, claims, starts and finishes it as succeeded with one artifact of
  // `bytes` bytes, as a worker would; returns the job.
  static std::shared_ptr<server::Job> run_to_end(RedisJobQueue& queue, RedisConnection& redis,
                                                 size_t bytes, const std::string& tenant = "t") {
    std::shared_ptr<server::Job> job;
    EXPECT_EQ(queue.submit(spec(tenant), job), JobQueue::Admission::kAccepted);
    const auto d = claim(queue, redis, "n1");
    int attempts = 0;
    EXPECT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
    auto run = queue.load(redis, d.id, false);
    run->artifacts = {artifact("sphere.glb", std::string(bytes, 'x'))};
    queue.finish(redis, d, *run, server::JobStatus::kSucceeded);
    return job;
  }
  static server::Artifact artifact(std::string name, std::string bytes) {
    return server::make_artifact(std::move(name), "application/octet-stream", std::move(bytes));
  }

  static inline int port_ = 0;
  static inline bool started_ = false;
  static inline std::filesystem::path dir_;
};

TEST_F(RedisQueueTest, CapacityHoldsAcrossReplicas) {
  RedisQueueLimits limits;
  limits.queue_capacity = 2;
  limits.tenant_max_queued = 1;
  RedisJobQueue a(address(), limits, nullptr), b(address(), limits, nullptr);
  std::shared_ptr<server::Job> job;
  EXPECT_EQ(a.submit(spec("t1"), job), JobQueue::Admission::kAccepted);
  EXPECT_EQ(b.submit(spec("t1"), job), JobQueue::Admission::kTenantQueueFull);
  EXPECT_EQ(b.submit(spec("t2"), job), JobQueue::Admission::kAccepted);
  EXPECT_EQ(a.submit(spec("t3"), job), JobQueue::Admission::kQueueFull);
  EXPECT_EQ(a.queued(), 2u);
  EXPECT_EQ(b.queue_position(*job), 2u);
}

TEST_F(RedisQueueTest, AJobFinishedTwiceKeepsTheFirstResult) {
  RedisQueueLimits limits;
  limits.visibility_timeout_seconds = 0.2;
  RedisJobQueue api(address(), limits, nullptr), node(address(), limits, nullptr);
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(api.submit(spec(), job), JobQueue::Admission::kAccepted);
  RedisConnection first(address()), second(address());
  const auto d1 = claim(node, first, "n1");
  int attempts = 0;
  ASSERT_EQ(node.start(first, d1, "n1", attempts), RedisJobQueue::Start::kRun);
  EXPECT_EQ(attempts, 1);
  // n1 falls silent past the visibility timeout: n2 takes the job over.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto d2 = claim(node, second, "n2");
  EXPECT_EQ(d2.id, job->id);
  ASSERT_EQ(node.start(second, d2, "n2", attempts), RedisJobQueue::Start::kRun);
  EXPECT_EQ(attempts, 2);
  // n1 was slow, not dead: it finishes first; n2's later answer must change nothing.
  auto run1 = node.load(first, job->id, true);
  ASSERT_TRUE(run1 && run1->spec);
  run1->artifacts = {artifact("sphere.glb", "first")};
  node.finish(first, d1, *run1, server::JobStatus::kSucceeded);
  auto run2 = node.load(second, job->id, false);
  run2->artifacts = {artifact("sphere.glb", "second")};
  node.finish(second, d2, *run2, server::JobStatus::kSucceeded);
  const auto found = api.find(job->id);
  ASSERT_TRUE(found.job);
  EXPECT_EQ(found.job->status, server::JobStatus::kSucceeded);
  const auto bytes = api.artifact(*found.job, "sphere.glb");
  ASSERT_TRUE(bytes);
  EXPECT_EQ(*bytes->bytes, "first");
  EXPECT_EQ(api.counts().running, 0u);  // both entries acknowledged
}

TEST_F(RedisQueueTest, CancelWhileQueuedIsFinalAndTheWorkerSkipsIt) {
  RedisJobQueue a(address(), {}, nullptr), b(address(), {}, nullptr);
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(a.submit(spec(), job), JobQueue::Admission::kAccepted);
  EXPECT_TRUE(b.cancel(job, "by a test"));
  EXPECT_EQ(a.find(job->id).job->status, server::JobStatus::kCancelled);
  EXPECT_EQ(a.queued(), 0u);
  RedisConnection redis(address());
  const auto d = claim(b, redis, "n1");
  int attempts = 0;
  EXPECT_EQ(b.start(redis, d, "n1", attempts), RedisJobQueue::Start::kSkip);
  EXPECT_FALSE(a.cancel(a.find(job->id).job, "again"));  // already finished
}

TEST_F(RedisQueueTest, AJobWhoseWorkersKeepDyingIsPoison) {
  RedisQueueLimits limits;
  limits.visibility_timeout_seconds = 0.1;
  limits.max_attempts = 2;
  RedisJobQueue queue(address(), limits, nullptr);
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  RedisConnection redis(address());
  int attempts = 0;
  for (int i = 1; i <= 2; ++i) {  // each worker dies without a word
    const auto d = claim(queue, redis, std::to_string(i) + "n");
    EXPECT_EQ(queue.start(redis, d, "n", attempts), RedisJobQueue::Start::kRun);
    EXPECT_EQ(attempts, i);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const auto d = claim(queue, redis, "n3");
  EXPECT_EQ(queue.start(redis, d, "n", attempts), RedisJobQueue::Start::kPoison);
  EXPECT_EQ(attempts, 2);
}

TEST_F(RedisQueueTest, ReleasedJobsKeepTheirPlaceAndUncountedAttempts) {
  RedisJobQueue queue(address(), {}, nullptr);
  std::shared_ptr<server::Job> first, second;
  ASSERT_EQ(queue.submit(spec(), first), JobQueue::Admission::kAccepted);
  ASSERT_EQ(queue.submit(spec(), second), JobQueue::Admission::kAccepted);
  RedisConnection redis(address());
  const auto d = claim(queue, redis, "n1");
  ASSERT_EQ(d.id, first->id);
  int attempts = 0;
  ASSERT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  queue.release(redis, d, false);  // the node stops: not the job's fault
  EXPECT_EQ(queue.find(first->id).job->status, server::JobStatus::kQueued);
  EXPECT_EQ(queue.queue_position(*first), 1u);  // ahead of the one submitted after it
  EXPECT_EQ(queue.queue_position(*second), 2u);
  const auto again = claim(queue, redis, "n2");  // `second`'s entry comes first now...
  const auto later = claim(queue, redis, "n2");  // ...then `first`'s new one
  EXPECT_EQ(again.id, second->id);
  EXPECT_EQ(later.id, first->id);
  ASSERT_EQ(queue.start(redis, later, "n2", attempts), RedisJobQueue::Start::kRun);
  EXPECT_EQ(attempts, 1);
}

TEST_F(RedisQueueTest, ATenantsRunningCapHoldsAcrossNodes) {
  RedisQueueLimits limits;
  limits.tenant_max_running = 1;
  RedisJobQueue api(address(), limits, nullptr), node(address(), limits, nullptr);
  std::shared_ptr<server::Job> a1, a2, b1;
  ASSERT_EQ(api.submit(spec("a"), a1), JobQueue::Admission::kAccepted);
  ASSERT_EQ(api.submit(spec("a"), a2), JobQueue::Admission::kAccepted);
  ASSERT_EQ(api.submit(spec("b"), b1), JobQueue::Admission::kAccepted);
  RedisConnection n1(address()), n2(address());
  int attempts = 0;
  const auto d1 = claim(node, n1, "n1");
  ASSERT_EQ(d1.id, a1->id);
  ASSERT_EQ(node.start(n1, d1, "n1", attempts), RedisJobQueue::Start::kRun);
  // Another node gets a's second job: a already runs one, so it waits, still queued...
  const auto d2 = claim(node, n2, "n2");
  ASSERT_EQ(d2.id, a2->id);
  EXPECT_EQ(node.start(n2, d2, "n2", attempts), RedisJobQueue::Start::kLater);
  EXPECT_EQ(api.find(a2->id).job->status, server::JobStatus::kQueued);
  // ...and b's job runs meanwhile.
  const auto d3 = claim(node, n2, "n2");
  ASSERT_EQ(d3.id, b1->id);
  EXPECT_EQ(node.start(n2, d3, "n2", attempts), RedisJobQueue::Start::kRun);
  // a's first job ends: its second may start.
  auto run = node.load(n1, a1->id, false);
  node.finish(n1, d1, *run, server::JobStatus::kSucceeded);
  const auto d4 = claim(node, n1, "n1");
  ASSERT_EQ(d4.id, a2->id);
  EXPECT_EQ(node.start(n1, d4, "n1", attempts), RedisJobQueue::Start::kRun);
}

TEST_F(RedisQueueTest, ResultsOverTheCapAreEvictedOldestFirstAndSay410) {
  RedisQueueLimits limits;
  limits.result_memory_bytes = 1500;
  RedisJobQueue queue(address(), limits, nullptr);
  RedisConnection redis(address());
  std::vector<std::shared_ptr<server::Job>> jobs(3);
  for (auto& job : jobs) {
    job = run_to_end(queue, redis, 600);
    std::this_thread::sleep_for(std::chrono::milliseconds(3));  // distinct end times
  }
  const auto oldest = queue.find(jobs[0]->id);
  EXPECT_FALSE(oldest.job);
  EXPECT_TRUE(oldest.evicted);  // 410, not 404
  EXPECT_TRUE(queue.find(jobs[1]->id).job);
  EXPECT_TRUE(queue.find(jobs[2]->id).job);
  EXPECT_EQ(queue.counts().result_bytes, 1200u);
  EXPECT_EQ(queue.counts().evicted, 1u);
  // DELETE forgets a finished job entirely: 404 afterwards, and its bytes are freed.
  EXPECT_TRUE(queue.remove(jobs[2]->id));
  const auto removed = queue.find(jobs[2]->id);
  EXPECT_FALSE(removed.job);
  EXPECT_FALSE(removed.evicted);
  EXPECT_EQ(queue.counts().result_bytes, 600u);
}

TEST_F(RedisQueueTest, ResultsLargerThanTheCapFailAs507) {
  RedisQueueLimits limits;
  limits.result_memory_bytes = 100;
  RedisJobQueue queue(address(), limits, nullptr);
  RedisConnection redis(address());
  const auto job = run_to_end(queue, redis, 600);
  const auto found = queue.find(job->id).job;
  ASSERT_TRUE(found);
  EXPECT_EQ(found->status, server::JobStatus::kFailed);
  ASSERT_TRUE(found->error);
  EXPECT_EQ(found->error->status, 507);
  EXPECT_EQ(found->error->problem, "result_too_large");
}

// The processes of one cluster publish their limits; one that differs from the process
// started before it hears so (and logs it).
TEST_F(RedisQueueTest, DifferentLimitsAreNoticed) {
  RedisQueueLimits api_limits, worker_limits;
  api_limits.result_memory_bytes = 128u << 20;
  RedisJobQueue api(address(), api_limits, nullptr);
  RedisJobQueue worker(address(), worker_limits, nullptr), same(address(), worker_limits, nullptr);
  EXPECT_EQ(api.publish_limits(), "");  // the first
  const std::string previous = worker.publish_limits();
  EXPECT_NE(previous.find("134217728"), std::string::npos) << previous;
  EXPECT_EQ(same.publish_limits(), "");
}

TEST_F(RedisQueueTest, RedisOutOfReachIsQueueUnavailable) {
  RedisAddress nowhere;
  nowhere.port = free_port();  // nothing listens there
  RedisJobQueue queue(nowhere, {}, nullptr);
  std::shared_ptr<server::Job> job;
  EXPECT_THROW(queue.submit(spec(), job), server::QueueUnavailable);
  EXPECT_THROW(queue.find("0123"), server::QueueUnavailable);
  EXPECT_FALSE(queue.accepting());
}

// The job as the API reads it back from Redis lists its artifacts without their bytes:
// the size shown is the size written (it was 0, and the page said "0.0 KiB").
TEST_F(RedisQueueTest, AListedArtifactShowsItsSize) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address());
  const auto job = run_to_end(queue, redis, 5000);
  const auto found = queue.find(job->id);
  ASSERT_TRUE(found.job);
  const nlohmann::json view = api::job_json(*found.job, 0);
  EXPECT_EQ(view["artifacts"]["sphere.glb"]["bytes"], 5000) << view.dump();
}

// Downloads of one artifact share one fetch's bytes: the second request gets the same
// object, and parallel requests make one fetch between them.
TEST_F(RedisQueueTest, DownloadsShareOneFetch) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address());
  const auto job = run_to_end(queue, redis, 1u << 20);
  const auto found = queue.find(job->id).job;
  ASSERT_TRUE(found);
  std::vector<api::SharedBytes> got(16);
  std::vector<std::thread> requests;
  for (size_t i = 0; i < got.size(); ++i)
    requests.emplace_back([&, i] { got[i] = queue.artifact(*found, "sphere.glb")->bytes; });
  for (auto& r : requests) r.join();
  for (const auto& g : got) EXPECT_EQ(g, got[0]);
  EXPECT_EQ(got[0]->size(), 1u << 20);
  EXPECT_FALSE(queue.artifact(*found, "remesh.glb"));
  EXPECT_FALSE(queue.gltf_view(*found, "remesh.glb"));
}

// A .gltf view in Redis mode: built from the fetched GLB once, the same bytes after.
TEST_F(RedisQueueTest, AGltfViewIsBuiltOnceFromTheFetchedGlb) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address());
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  const auto d = claim(queue, redis, "n1");
  int attempts = 0;
  ASSERT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  GlbMesh mesh;
  const PolygonMesh sphere = testing::icosphere(1);
  mesh.positions = sphere.positions;
  mesh.triangles = fan_triangulate(sphere).triangles;
  const std::string glb = format_glb(mesh);
  auto run = queue.load(redis, d.id, false);
  run->artifacts = {server::make_artifact("sphere.glb", "model/gltf-binary", glb)};
  queue.finish(redis, d, *run, server::JobStatus::kSucceeded);
  const auto found = queue.find(job->id).job;
  ASSERT_TRUE(found);
  const api::SharedBytes first = queue.gltf_view(*found, "sphere.glb");
  ASSERT_TRUE(first);
  EXPECT_EQ(*first, glb_to_gltf(glb));
  EXPECT_EQ(queue.gltf_view(*queue.find(job->id).job, "sphere.glb"), first);  // kept
}

// Two worker nodes starting together on a fresh Redis both find no group and both create
// it: the second XGROUP CREATE answers BUSYGROUP, which is "already done", not "Redis is
// unavailable" (that was logged as redis_unavailable and retried 2 s later).
TEST_F(RedisQueueTest, AnExistingConsumerGroupIsNotRedisUnavailable) {
  RedisConnection redis(address());
  redis.command({"XGROUP", "CREATE", "probe", "g", "0", "MKSTREAM"});
  try {
    redis.command({"XGROUP", "CREATE", "probe", "g", "0", "MKSTREAM"});
    FAIL() << "a second XGROUP CREATE succeeded";
  } catch (const server::RedisUnavailable& e) {
    FAIL() << "classed as unavailable: " << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("BUSYGROUP"), std::string::npos) << e.what();
  }
}

TEST_F(RedisQueueTest, WorkersStartingTogetherBothClaim) {
  for (int round = 0; round < 10; ++round) {
    RedisConnection(address()).command({"FLUSHALL"});
    RedisJobQueue a(address(), {}, nullptr), b(address(), {}, nullptr);
    RedisConnection ra(address()), rb(address());
    ra.command({"PING"}), rb.command({"PING"});  // connected, so both claims start at once
    std::atomic<int> ready{0};
    std::string errors;
    std::mutex errors_mutex;
    auto start = [&](RedisJobQueue& queue, RedisConnection& redis, const char* consumer) {
      ++ready;
      while (ready < 2) std::this_thread::yield();
      try {
        queue.claim(redis, consumer, 0.01);
      } catch (const std::exception& e) {
        std::lock_guard lock(errors_mutex);
        errors += std::string(consumer) + ": " + e.what() + "\n";
      }
    };
    std::thread first(start, std::ref(a), std::ref(ra), "n1");
    std::thread second(start, std::ref(b), std::ref(rb), "n2");
    first.join();
    second.join();
    ASSERT_EQ(errors, "") << "round " << round;
  }
  // The group both made is the one jobs reach.
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address());
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  EXPECT_EQ(claim(queue, redis, "n1").id, job->id);
}

// A worker of the process that submitted a job tells "running" only after the job's
// "queued" was told (the observer writes the job log), however slow that was.
TEST_F(RedisQueueTest, AWorkerHereTellsRunningAfterQueued) {
  std::mutex order_mutex;
  std::vector<std::string> order;
  RedisJobQueue queue(address(), {},
                      [&](const std::shared_ptr<server::Job>&, server::JobStatus status) {
                        if (status != server::JobStatus::kQueued) return;
                        std::this_thread::sleep_for(std::chrono::milliseconds(200));
                        std::lock_guard lock(order_mutex);
                        order.push_back("queued");
                      });
  RedisConnection redis(address());
  std::thread worker([&] {
    const auto delivery = claim(queue, redis, "n1");
    queue.wait_until_told(delivery.id);
    std::lock_guard lock(order_mutex);
    order.push_back("running");
  });
  std::shared_ptr<server::Job> job;
  EXPECT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  worker.join();
  EXPECT_EQ(order, (std::vector<std::string>{"queued", "running"}));
}

// Security III, 4: a Redis that stalls for 3 s while a job is being admitted. Whatever the
// answer, it is the truth: accepted means stored and queued; QueueUnavailable (503) means
// nothing was stored, even once Redis runs what it had waiting. Three stalls: DEBUG SLEEP
// under the default 5 s payload timeout (the submission waits it out), and DEBUG SLEEP and
// CLIENT PAUSE WRITE (reads pass, scripts wait) under a 1 s timeout, which the stall
// outlasts.
TEST_F(RedisQueueTest, AStallDuringAdmissionGives202OrNothingStored) {
  struct Case {
    const char* name;
    std::vector<std::string_view> stall;
    double timeout;
    bool accepted;  // expected
  };
  const std::vector<Case> cases = {
      {"DEBUG SLEEP 3, 5 s timeout", {"DEBUG", "SLEEP", "3"}, 5, true},
      {"DEBUG SLEEP 3, 1 s timeout", {"DEBUG", "SLEEP", "3"}, 1, false},
      {"CLIENT PAUSE 3000 WRITE, 1 s timeout", {"CLIENT", "PAUSE", "3000", "WRITE"}, 1, false},
  };
  for (const Case& c : cases) {
    RedisConnection(address()).command({"FLUSHALL"});
    RedisQueueLimits limits;
    limits.payload_timeout_seconds = c.timeout;
    RedisJobQueue queue(address(), limits, nullptr);
    RedisConnection(address()).command({"PING"});
    const auto stall_start = std::chrono::steady_clock::now();
    std::string stall_error;
    std::thread stall([&] {
      try {
        RedisConnection(address()).command_within(c.stall, 10);
      } catch (const std::exception& e) {
        stall_error = e.what();
      }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the stall has begun
    const auto submit_start = std::chrono::steady_clock::now();
    std::shared_ptr<server::Job> job;
    bool accepted = false;
    try {
      accepted = queue.submit(spec(), job) == JobQueue::Admission::kAccepted;
    } catch (const server::QueueUnavailable& e) {
      std::cout << "  " << c.name << ": 503: " << e.what() << "\n";
    }
    const double answered_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - submit_start).count();
    stall.join();
    ASSERT_EQ(stall_error, "") << c.name;
    // Past the stall, whatever Redis had waiting has run.
    std::this_thread::sleep_until(stall_start + std::chrono::milliseconds(3500));
    RedisConnection redis(address());
    const size_t jobs = redis.command({"KEYS", "spheremap:job:*"}).size();
    const long long entries = redis.command({"XLEN", "spheremap:jobs"}).integer();
    std::cout << "  " << c.name << ": " << (accepted ? "accepted" : "503") << " after "
              << answered_s << " s; jobs stored " << jobs << ", entries " << entries << "\n";
    EXPECT_EQ(accepted, c.accepted) << c.name;
    EXPECT_EQ(jobs, accepted ? 1u : 0u) << c.name;
    EXPECT_EQ(entries, accepted ? 1 : 0) << c.name;
    EXPECT_EQ(queue.queued(), accepted ? 1u : 0u) << c.name;
    if (accepted) {
      EXPECT_TRUE(queue.find(job->id).job) << c.name;
    }
  }
}

// A TCP relay between the queue and Redis that can hold Redis's answers on the
// connections open now (after letting `pass` more through), as a network or a Redis that
// stops answering would: the commands arrive and run, their answers do not come back in
// time. Connections opened later are relayed at once.
class AnswerHoldingRelay {
 public:
  explicit AnswerHoldingRelay(int redis_port) : redis_port_(redis_port) {
    listener_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address);
    socklen_t size = sizeof address;
    getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &size);
    port_ = ntohs(address.sin_port);
    listen(listener_, 16);
    acceptor_ = std::thread([this] { accept_loop(); });
  }
  ~AnswerHoldingRelay() {
    shutdown(listener_, SHUT_RDWR);
    close(listener_);
    acceptor_.join();
    for (std::thread& t : pumps_) t.join();
  }
  int port() const { return port_; }
  // Answers on the connections open now, after `pass` more of them, wait `seconds`.
  void hold(int pass, double seconds) {
    pass_ = pass;
    release_ = std::chrono::steady_clock::now() +
               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(seconds));
    held_below_ = opened_.load();
  }

 private:
  void accept_loop() {
    for (;;) {
      const int client = accept(listener_, nullptr, nullptr);
      if (client < 0) return;
      const int redis = testing_connect(redis_port_);
      const int number = opened_++;
      pumps_.emplace_back([this, client, redis] { pump(client, redis, false); });
      pumps_.emplace_back([this, client, redis, number] { pump(redis, client, true, number); });
    }
  }
  static int testing_connect(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
    return fd;
  }
  void pump(int from, int to, bool answers, int number = 0) {
    char buffer[65536];
    for (;;) {
      const ssize_t got = recv(from, buffer, sizeof buffer, 0);
      if (got <= 0) break;
      if (answers && number < held_below_ && pass_-- <= 0)
        std::this_thread::sleep_until(release_.load());
      if (send(to, buffer, static_cast<size_t>(got), MSG_NOSIGNAL) != got) break;
    }
    shutdown(to, SHUT_RDWR);
    shutdown(from, SHUT_RDWR);
  }

  const int redis_port_;
  int listener_ = -1, port_ = 0;
  std::atomic<int> opened_{0}, held_below_{0}, pass_{0};
  std::atomic<std::chrono::steady_clock::time_point> release_{};
  std::thread acceptor_;
  std::vector<std::thread> pumps_;  // touched by the acceptor only, joined at the end
};

// A submission that Redis stored but whose answer was lost (held 3 s, past the 1 s
// timeout) is found stored and answered as accepted (202), not 503.
TEST_F(RedisQueueTest, ASubmissionStoredButUnansweredIsAccepted) {
  AnswerHoldingRelay relay(port_);
  RedisAddress through = address();
  through.port = relay.port();
  RedisQueueLimits limits;
  limits.payload_timeout_seconds = 1;
  RedisJobQueue queue(through, limits, nullptr);
  std::shared_ptr<server::Job> first, second;
  // The first submission opens the pooled connection and learns Redis's value limit.
  ASSERT_EQ(queue.submit(spec(), first), JobQueue::Admission::kAccepted);
  relay.hold(1, 3);  // TIME's answer passes; the submission's is held
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(queue.submit(spec(), second), JobQueue::Admission::kAccepted);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "  accepted after " << seconds << " s (answer held 3 s, timeout 1 s)\n";
  EXPECT_GE(seconds, 1.0);  // it did time out
  ASSERT_TRUE(second);
  EXPECT_TRUE(RedisJobQueue(address(), {}, nullptr).find(second->id).job);
  EXPECT_EQ(integer({"XLEN", "spheremap:jobs"}), 2);
  std::this_thread::sleep_until(start + std::chrono::milliseconds(3200));  // let it go
}

TEST_F(RedisQueueTest, ARetriedSubmissionWithTheSameKeyIsOneJob) {
  RedisQueueLimits limits;
  limits.tenant_max_queued = 1;  // a replay takes no queue slot
  RedisJobQueue a(address(), limits, nullptr), b(address(), limits, nullptr);
  std::shared_ptr<server::Job> first, again, other;
  ASSERT_EQ(a.submit(spec("t1", "order-17"), first), JobQueue::Admission::kAccepted);
  ASSERT_EQ(b.submit(spec("t1", "order-17"), again), JobQueue::Admission::kReplayed);
  EXPECT_EQ(again->id, first->id);
  ASSERT_TRUE(b.replay("t1", "order-17"));
  EXPECT_EQ(b.replay("t1", "order-17")->id, first->id);
  EXPECT_FALSE(b.replay("t1", "order-18"));
  EXPECT_EQ(a.queued(), 1u);
  EXPECT_EQ(integer({"XLEN", "spheremap:jobs"}), 1);
  // Another tenant's same key is another job; "t" + "1:order-17" is not "t1" + "order-17".
  ASSERT_EQ(a.submit(spec("t2", "order-17"), other), JobQueue::Admission::kAccepted);
  EXPECT_NE(other->id, first->id);
  EXPECT_FALSE(a.replay("t", "1:order-17"));
  // Once the job is forgotten (DELETE, eviction), the key makes a new one.
  RedisConnection redis(address());
  const auto d = claim(a, redis, "n1");
  int attempts = 0;
  ASSERT_EQ(a.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  auto run = a.load(redis, d.id, false);
  a.finish(redis, d, *run, server::JobStatus::kSucceeded);
  ASSERT_TRUE(a.remove(first->id));
  std::shared_ptr<server::Job> fresh;
  ASSERT_EQ(a.submit(spec("t1", "order-17"), fresh), JobQueue::Admission::kAccepted);
  EXPECT_NE(fresh->id, first->id);
}

// Permanent failures are not "retry later": a prepared job over Redis's largest value
// (proto-max-bulk-len, lowered here to its 1 MB minimum) is kTooLarge (413), and a Redis
// out of memory (maxmemory reached, noeviction) is kStorageFull (507); nothing is stored.
TEST_F(RedisQueueTest, PermanentAdmissionFailuresAre413And507) {
  RedisConnection admin(address());
  admin.command({"CONFIG", "SET", "proto-max-bulk-len", "1mb"});
  {
    RedisJobQueue queue(address(), {}, nullptr);
    std::shared_ptr<server::Job> job;
    EXPECT_EQ(queue.submit(spec("t", "", 6), job), JobQueue::Admission::kTooLarge);
    EXPECT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);  // small ones go on
  }
  admin.command({"CONFIG", "SET", "proto-max-bulk-len", "512mb"});
  admin.command({"CONFIG", "SET", "maxmemory-policy", "noeviction"});
  admin.command({"CONFIG", "SET", "maxmemory", "1"});
  std::shared_ptr<server::Job> job;
  RedisJobQueue queue(address(), {}, nullptr);
  const auto admission = queue.submit(spec(), job);
  admin.command({"CONFIG", "SET", "maxmemory", "0"});
  EXPECT_EQ(admission, JobQueue::Admission::kStorageFull);
  EXPECT_EQ(queue.queued(), 1u);  // the small job from before only
}

// Results are written once: a finish retried after its staged write went through (its
// answer lost) does not send the artifacts again, nor does a finish retried after it
// completed.
TEST_F(RedisQueueTest, AFinishRetriedDoesNotSendTheResultsAgain) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address());
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  const auto d = claim(queue, redis, "n1");
  int attempts = 0;
  ASSERT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  const std::string result(2u << 20, 'r');
  // The first try staged the artifact, then lost Redis before its finish script.
  redis.command({"HSET", "spheremap:files:" + d.id + ":" + d.entry, "sphere.glb", result});
  auto run = queue.load(redis, d.id, false);
  run->artifacts = {artifact("sphere.glb", result)};
  const long long before = bytes_received();
  queue.finish(redis, d, *run, server::JobStatus::kSucceeded);  // the retry
  queue.finish(redis, d, *run, server::JobStatus::kSucceeded);  // and one more
  const long long sent = bytes_received() - before;
  std::cout << "  two retried finishes sent " << sent << " bytes (the result: " << result.size()
            << ")\n";
  EXPECT_LT(sent, 100000);
  const auto found = queue.find(job->id).job;
  ASSERT_TRUE(found);
  EXPECT_EQ(found->status, server::JobStatus::kSucceeded);
  EXPECT_EQ(*queue.artifact(*found, "sphere.glb")->bytes, result);
  EXPECT_EQ(queue.counts().result_bytes, result.size());  // counted once
}

// A worker beats until its result is stored (so that a long finish is not taken over and
// run again): a beat after the job ended, even after it was evicted, changes nothing and
// never brings back the job's hash.
TEST_F(RedisQueueTest, AHeartbeatAfterTheEndChangesNothing) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address()), beat(address());
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  const auto d = claim(queue, redis, "n1");
  int attempts = 0;
  ASSERT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  auto run = queue.load(redis, d.id, false);
  run->progress.stage = "optimize";
  EXPECT_FALSE(queue.heartbeat(beat, "n1", d, *run));
  EXPECT_EQ(queue.find(job->id).job->progress.stage, "optimize");
  ASSERT_TRUE(queue.cancel(job, "by a test"));  // running: the flag, read by the next beat
  EXPECT_TRUE(queue.heartbeat(beat, "n1", d, *run));
  queue.finish(redis, d, *run, server::JobStatus::kCancelled);
  run->progress.stage = "late";
  EXPECT_FALSE(queue.heartbeat(beat, "n1", d, *run));
  EXPECT_EQ(queue.find(job->id).job->progress.stage, "cancelled");
  ASSERT_TRUE(queue.remove(job->id));
  EXPECT_FALSE(queue.heartbeat(beat, "n1", d, *run));
  EXPECT_EQ(integer({"EXISTS", "spheremap:job:" + job->id}), 0);
  EXPECT_EQ(queue.counts().running, 0u);  // the beat did not claim the entry back
}

// Results Redis has no memory for (maxmemory reached, noeviction): the job fails 507
// result_storage_full at once (the finish script, which starts by acknowledging, still
// runs), rather than the worker offering the artifacts again and again.
TEST_F(RedisQueueTest, ResultsRedisHasNoRoomForFailAs507) {
  RedisJobQueue queue(address(), {}, nullptr);
  RedisConnection redis(address()), admin(address());
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
  const auto d = claim(queue, redis, "n1");
  int attempts = 0;
  ASSERT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
  auto run = queue.load(redis, d.id, false);
  run->artifacts = {artifact("sphere.glb", std::string(100000, 'r'))};
  admin.command({"CONFIG", "SET", "maxmemory-policy", "noeviction"});
  admin.command({"CONFIG", "SET", "maxmemory", "1"});
  try {
    queue.finish(redis, d, *run, server::JobStatus::kSucceeded);
  } catch (const server::RedisUnavailable&) {
    // a Redis that refuses even the verdict: the worker retries (without the artifacts)
    admin.command({"CONFIG", "SET", "maxmemory", "0"});
    queue.finish(redis, d, *run, server::JobStatus::kSucceeded);
  }
  admin.command({"CONFIG", "SET", "maxmemory", "0"});
  const auto found = queue.find(job->id).job;
  ASSERT_TRUE(found);
  EXPECT_EQ(found->status, server::JobStatus::kFailed);
  ASSERT_TRUE(found->error);
  EXPECT_EQ(found->error->status, 507);
  EXPECT_EQ(found->error->problem, "result_storage_full");
  EXPECT_EQ(queue.counts().running, 0u);  // acknowledged
}

// Security III, 6: tenant_result_memory_bytes holds in Redis mode as in memory mode: a
// tenant over its share loses its own oldest results, never another tenant's.
TEST_F(RedisQueueTest, ATenantsResultsEvictOnlyItsOwn) {
  RedisQueueLimits limits;
  limits.tenant_result_memory_bytes = 1500;
  RedisJobQueue queue(address(), limits, nullptr);
  RedisConnection redis(address());
  const auto quiet = run_to_end(queue, redis, 600, "quiet");
  std::vector<std::shared_ptr<server::Job>> busy;
  for (int i = 0; i < 4; ++i) {
    busy.push_back(run_to_end(queue, redis, 600, "busy"));
    std::this_thread::sleep_for(std::chrono::milliseconds(3));  // distinct end times
  }
  EXPECT_TRUE(queue.find(quiet->id).job);  // untouched
  for (int i = 0; i < 2; ++i) {
    const auto old = queue.find(busy[i]->id);
    EXPECT_FALSE(old.job) << i;
    EXPECT_TRUE(old.evicted) << i;  // 410
  }
  EXPECT_TRUE(queue.find(busy[2]->id).job);
  EXPECT_TRUE(queue.find(busy[3]->id).job);
  EXPECT_EQ(queue.counts().result_bytes, 1800u);
  EXPECT_EQ(queue.counts().evicted, 2u);
  RedisConnection check(address());
  EXPECT_EQ(check.command({"HGET", "spheremap:tenant_bytes", "busy"}).integer(), 1200);
  EXPECT_EQ(check.command({"HGET", "spheremap:tenant_bytes", "quiet"}).integer(), 600);
  // DELETE frees the tenant's share too.
  EXPECT_TRUE(queue.remove(quiet->id));
  EXPECT_TRUE(check.command({"HGET", "spheremap:tenant_bytes", "quiet"}).is_nil());
}

// The same over HTTP, on an API-only node of the Redis queue: the Idempotency-Key replay,
// and the permanent refusals as their status codes (413, 507), not 503.
TEST_F(RedisQueueTest, OverHttpKeysReplayAndPermanentFailuresAre413And507) {
  server::ServerConfig config;
  config.queue = "redis://127.0.0.1:" + std::to_string(port_);
  config.workers = 0;
  config.http_threads = 4;
  testing::TestServer server(config);
  auto client = server.client();
  auto glb_of = [](int subdivisions) {
    const PolygonMesh mesh = testing::icosphere(subdivisions);
    GlbMesh glb;
    glb.positions = mesh.positions;
    glb.triangles = fan_triangulate(mesh).triangles;
    return format_glb(glb);
  };
  const std::string small = glb_of(2);
  const httplib::Headers key = {{"Idempotency-Key", "upload-1"}};
  auto first = client.Post("/v1/jobs", key, small, "model/gltf-binary");
  auto again = client.Post("/v1/jobs", key, small, "model/gltf-binary");
  ASSERT_TRUE(first && again);
  ASSERT_EQ(first->status, 202) << first->body;
  EXPECT_EQ(again->status, 202);
  EXPECT_EQ(nlohmann::json::parse(again->body)["id"], nlohmann::json::parse(first->body)["id"]);
  EXPECT_EQ(again->get_header_value("Idempotent-Replayed"), "true");
  EXPECT_EQ(integer({"XLEN", "spheremap:jobs"}), 1);

  RedisConnection admin(address());
  admin.command({"CONFIG", "SET", "maxmemory-policy", "noeviction"});
  admin.command({"CONFIG", "SET", "maxmemory", "1"});
  auto full = client.Post("/v1/jobs", small, "model/gltf-binary");
  admin.command({"CONFIG", "SET", "maxmemory", "0"});
  ASSERT_TRUE(full);
  EXPECT_EQ(full->status, 507) << full->body;
  EXPECT_NE(full->body.find("queue_storage_full"), std::string::npos) << full->body;
  EXPECT_FALSE(full->has_header("Retry-After"));

  // The server learnt Redis's value limit at its first submission: a fresh server learns
  // the lowered one.
  admin.command({"CONFIG", "SET", "proto-max-bulk-len", "1mb"});
  {
    testing::TestServer lowered(config);
    auto large = lowered.client().Post("/v1/jobs", glb_of(6), "model/gltf-binary");
    admin.command({"CONFIG", "SET", "proto-max-bulk-len", "512mb"});
    ASSERT_TRUE(large);
    EXPECT_EQ(large->status, 413) << large->body;
    EXPECT_NE(large->body.find("queue_entry_too_large"), std::string::npos) << large->body;
  }
  admin.command({"CONFIG", "SET", "proto-max-bulk-len", "512mb"});
  EXPECT_EQ(integer({"XLEN", "spheremap:jobs"}), 1);  // nothing more was stored
}

TEST(RedisAddress, ParsesAndRefuses) {
  const RedisAddress a = RedisAddress::parse("redis://cache.internal:7000/3");
  EXPECT_EQ(a.host, "cache.internal");
  EXPECT_EQ(a.port, 7000);
  EXPECT_EQ(a.db, 3);
  EXPECT_EQ(RedisAddress::parse("redis://10.0.0.2").port, 6379);
  EXPECT_THROW(RedisAddress::parse("http://x"), std::invalid_argument);
  EXPECT_THROW(RedisAddress::parse("redis://x:99999"), std::invalid_argument);
  EXPECT_THROW(RedisAddress::parse("redis://user:pw@x:1"), std::invalid_argument);
  EXPECT_THROW(RedisAddress::parse("redis://x:1/db"), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
