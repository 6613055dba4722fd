// The in-memory job store (server/job_store.h): a job's status changes reach the
// observer (the service's log and metrics) in the order they happened.
#include "server/job_store.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using server::JobStatus;

// A worker waits for the job while it is submitted; the observer is slow to write the
// "queued" line (a busy stderr): "running" must still come after it. It came first when
// the store told "queued" after letting workers see the job.
TEST(JobStore, QueuedIsToldBeforeRunning) {
  std::mutex order_mutex;
  std::vector<JobStatus> order;
  server::JobStore store({}, [&](const std::shared_ptr<server::Job>&, JobStatus status) {
    if (status == JobStatus::kQueued) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::lock_guard lock(order_mutex);
    order.push_back(status);
  });
  std::shared_ptr<server::Job> taken;
  std::thread worker([&] { taken = store.next(); });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the worker waits in next()
  auto spec = std::make_unique<server::JobSpec>();
  spec->input = testing::icosphere(1);
  std::shared_ptr<server::Job> job;
  ASSERT_EQ(store.submit(std::move(spec), job), server::JobQueue::Admission::kAccepted);
  worker.join();
  ASSERT_EQ(taken, job);
  store.finish(job, JobStatus::kSucceeded);
  std::lock_guard lock(order_mutex);
  ASSERT_EQ(order.size(), 3u);
  EXPECT_EQ(order[0], JobStatus::kQueued);
  EXPECT_EQ(order[1], JobStatus::kRunning);
  EXPECT_EQ(order[2], JobStatus::kSucceeded);
}

// Idempotency-Key in memory mode: a tenant's retry is the same job, even when the queue is
// full (it takes no slot); another tenant's same key is its own job; once the job is
// forgotten (DELETE here), the key makes a new one.
TEST(JobStore, AnIdempotencyKeyIsOneJobPerTenantWhileItIsKept) {
  server::StoreLimits limits;
  limits.queue_capacity = 2;
  server::JobStore store(limits, nullptr);
  auto spec = [](const std::string& tenant, const std::string& key) {
    auto s = std::make_unique<server::JobSpec>();
    s->input = testing::icosphere(1);
    s->tenant = tenant;
    s->idempotency_key = key;
    return s;
  };
  using Admission = server::JobQueue::Admission;
  std::shared_ptr<server::Job> a, again, b, c;
  ASSERT_EQ(store.submit(spec("alpha", "k"), a), Admission::kAccepted);
  ASSERT_EQ(store.submit(spec("beta", "k"), b), Admission::kAccepted);
  EXPECT_NE(a, b);
  EXPECT_EQ(store.submit(spec("gamma", "k"), c), Admission::kQueueFull);
  EXPECT_EQ(store.submit(spec("alpha", "k"), again), Admission::kReplayed);  // full, yet
  EXPECT_EQ(again, a);
  EXPECT_EQ(store.replay("alpha", "k"), a);
  EXPECT_EQ(store.replay("alpha", "other"), nullptr);
  EXPECT_EQ(store.queued(), 2u);
  store.cancel(a, "test");
  ASSERT_TRUE(store.remove(a->id));
  EXPECT_EQ(store.replay("alpha", "k"), nullptr);
  std::shared_ptr<server::Job> fresh;
  ASSERT_EQ(store.submit(spec("alpha", "k"), fresh), Admission::kAccepted);
  EXPECT_NE(fresh->id, a->id);
}

}  // namespace
}  // namespace spheremap
