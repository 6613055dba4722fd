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
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/job_view.h"
#include "core/map/pipeline.h"
#include "server/redis_queue.h"
#include "tests/mesh_generators.h"

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
                                " --dir " + dir_.string() + " --pidfile " +
                                (dir_ / "redis.pid").string() + " --logfile " +
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
  static std::unique_ptr<server::JobSpec> spec(const std::string& tenant = "t") {
    auto s = std::make_unique<server::JobSpec>();
    s->input = testing::icosphere(1);
    s->prepared = prepare_mesh(s->input, {});
    s->tenant = tenant;
    return s;
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
                                                 size_t bytes) {
    std::shared_ptr<server::Job> job;
    EXPECT_EQ(queue.submit(spec(), job), JobQueue::Admission::kAccepted);
    const auto d = claim(queue, redis, "n1");
    int attempts = 0;
    EXPECT_EQ(queue.start(redis, d, "n1", attempts), RedisJobQueue::Start::kRun);
    auto run = queue.load(redis, d.id, false);
    run->artifacts = {artifact("sphere.glb", std::string(bytes, 'x'))};
    queue.finish(redis, d, *run, server::JobStatus::kSucceeded);
    return job;
  }
  static server::Artifact artifact(std::string name, std::string bytes) {
    const size_t size = bytes.size();
    return {std::move(name), "application/octet-stream", std::move(bytes), size};
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
  EXPECT_EQ(bytes->bytes, "first");
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
