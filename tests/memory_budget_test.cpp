// The node's memory budget for running jobs (server/memory_budget.h): charges add up to
// at most the budget, waiters are served in order of arrival (a large job is not
// overtaken for ever), a waiter can give up, and a job above the whole budget runs alone.
#include "server/memory_budget.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "server/job_memory.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using server::MemoryBudget;

const auto never = [] { return false; };

TEST(MemoryBudget, ChargesAddUpToTheBudgetAndComeBack) {
  MemoryBudget budget(100);
  auto a = budget.acquire(60, never);
  ASSERT_TRUE(a);
  EXPECT_EQ(budget.in_use(), 60u);
  {
    auto b = budget.acquire(40, never);
    ASSERT_TRUE(b);
    EXPECT_EQ(budget.in_use(), 100u);
  }
  EXPECT_EQ(budget.in_use(), 60u);
  // Above the whole budget: charged the whole budget, so it waits for everything else.
  std::atomic<bool> got{false};
  std::thread huge([&] {
    auto c = budget.acquire(1000, never);
    EXPECT_EQ(c->bytes(), 100u);
    got = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  EXPECT_FALSE(got);
  a.reset();
  huge.join();
  EXPECT_TRUE(got);
  EXPECT_EQ(budget.in_use(), 0u);
}

TEST(MemoryBudget, WaitersAreServedInOrderOfArrival) {
  MemoryBudget budget(100);
  auto first = budget.acquire(70, never);
  std::vector<int> order;
  std::mutex order_mutex;
  // The large one arrives first and must not be overtaken by the small one, which
  // would fit now (and cannot run beside the large one: 80 + 30 > 100).
  std::thread large([&] {
    auto c = budget.acquire(80, never);
    std::lock_guard lock(order_mutex);
    order.push_back(80);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::thread small([&] {
    auto c = budget.acquire(30, never);
    std::lock_guard lock(order_mutex);
    order.push_back(30);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  {
    std::lock_guard lock(order_mutex);
    EXPECT_TRUE(order.empty());
  }
  first.reset();
  large.join();
  small.join();
  EXPECT_EQ(order, (std::vector<int>{80, 30}));
}

TEST(MemoryBudget, AWaiterThatGivesUpLeavesTheLine) {
  MemoryBudget budget(100);
  auto held = budget.acquire(100, never);
  std::atomic<bool> cancel{false};
  std::thread waiter([&] { EXPECT_FALSE(budget.acquire(10, [&] { return cancel.load(); })); });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  cancel = true;
  waiter.join();
  held.reset();
  EXPECT_TRUE(budget.acquire(100, never));  // nobody left ahead of it
}

TEST(JobMemory, EstimatesGrowWithTrianglesAndTheRemesh) {
  api::JobSpec spec;
  spec.input.positions.resize(4);
  spec.input.indices = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
  spec.input.offsets = {0, 3, 6, 9, 12};
  const size_t small = server::estimated_job_bytes(spec);
  EXPECT_EQ(small, (16u << 20) + 400 * 4);
  spec.outputs = {"sphere", "remesh"};
  spec.remesh_resolution = 1024;
  EXPECT_EQ(server::estimated_job_bytes(spec),
            small + (96u << 20) + server::kRemeshBytesPerSample * 1024 * 1024);
}

// A part costs its own map and file whatever its size, and several parts' remesh grids
// hold up to 4 grids' samples together (part_grids.h).
TEST(JobMemory, EstimatesCountThePartsAndTheirRemeshGrids) {
  api::JobSpec spec;
  spec.input.positions.resize(4);
  spec.input.indices = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
  spec.input.offsets = {0, 3, 6, 9, 12};
  spec.outputs = {"sphere", "remesh"};
  spec.remesh_resolution = 256;
  const size_t whole = server::estimated_job_bytes(spec);
  spec.prepared.parts.resize(1);
  const size_t one_part = server::estimated_job_bytes(spec);
  EXPECT_EQ(one_part, whole + 20000);
  spec.prepared.parts.resize(500);
  EXPECT_EQ(server::estimated_job_bytes(spec),
            whole + 500 * 20000 + server::kRemeshBytesPerSample * 256 * 256);
}

TEST(JobMemory, TheRemeshCountsItsDecodedBaseColourPixels) {
  api::JobSpec spec;
  spec.input = read_gltf(testing::as_bytes(testing::textured_glb(testing::horseshoe())), {},
                         nullptr, nullptr, &spec.look);
  spec.outputs = {"sphere", "remesh"};
  spec.remesh_resolution = 64;
  const size_t textured = server::estimated_job_bytes(spec);
  spec.look.primitives[0].material = -1;  // no texture sampled
  EXPECT_EQ(textured - server::estimated_job_bytes(spec), 4u * 16 * 16);
}

TEST(JobMemory, TheInputsImagesCountOnceEach) {
  api::JobSpec spec;
  spec.input = read_gltf(testing::as_bytes(testing::many_images_naming_one_view(1 << 20, 100)), {},
                         nullptr, nullptr, &spec.look);
  const size_t with_images = server::estimated_job_bytes(spec);
  const size_t image_bytes = spec.look.image_data[0].size() + spec.look.image_data[1].size();
  spec.look.image_data.clear();
  // Held, and written into sphere.glb: twice the distinct bytes, not 101 x.
  EXPECT_EQ(with_images - server::estimated_job_bytes(spec), 2 * image_bytes);
  EXPECT_LT(2 * image_bytes, size_t{3} << 20);
}

// An envelope left to the worker is charged with the job: its grid at the peak, and the
// original kept beside it.
TEST(JobMemory, APendingEnvelopeCountsItsGrid) {
  api::JobSpec spec;
  spec.input = testing::torus(24, 12);
  const size_t plain = server::estimated_job_bytes(spec);
  PrepareOptions wrap;
  wrap.method = PrepareMethod::kWrap;
  wrap.defer_envelopes = true;
  spec.prepared = prepare_input(spec.input, nullptr, wrap);
  const size_t voxels = spec.prepared.pending.grid_voxels;
  EXPECT_GT(voxels, size_t{1} << 20);  // the default 256 voxels across the diagonal
  EXPECT_GE(server::estimated_job_bytes(spec), plain + 16 * voxels);
}

}  // namespace
}  // namespace spheremap
