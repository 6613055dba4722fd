// Downloads share the artifact's bytes (api/shared_body.h): parallel GETs of a large
// artifact cost its size once, and a .gltf view is built once and kept with the job.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/io/glb_writer.h"
#include "server/shared_bytes_cache.h"
#include "tests/mesh_generators.h"
#include "tests/test_server.h"

namespace spheremap {
namespace {

using nlohmann::json;
using testing::TestServer;

// This process's resident memory now, from /proc/self/status (VmRSS, in bytes).
size_t resident_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.starts_with("VmRSS:")) return std::stoull(line.substr(6)) * 1024;
  return 0;
}

server::ServerConfig download_config() {
  server::ServerConfig config;
  config.workers = 1;
  config.threads_per_job = 1;
  config.http_threads = 24;
  config.max_connections_per_address = 0;
  config.worker_executable = SPHEREMAP_BINARY;
  return config;
}

// A small job run to its end; returns its id.
std::string finished_job(httplib::Client& client) {
  GlbMesh glb;
  const PolygonMesh mesh = testing::icosphere(2);
  glb.positions = mesh.positions;
  glb.triangles = fan_triangulate(mesh).triangles;
  auto submitted = client.Post("/v1/jobs", format_glb(glb), "model/gltf-binary");
  EXPECT_EQ(submitted->status, 202) << submitted->body;
  const std::string id = json::parse(submitted->body)["id"];
  for (int i = 0; i < 6000; ++i) {
    const json job = json::parse(client.Get(("/v1/jobs/" + id).c_str())->body);
    if (job["status"] != "queued" && job["status"] != "running") {
      EXPECT_EQ(job["status"], "succeeded") << job.dump(2);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return id;
}

// 16 parallel GETs of a 64 MB artifact: the server's memory grows by far less than one
// copy of it (each GET copied it before: 16 copies, 1 GB).
TEST(Downloads, ParallelGetsOfALargeArtifactShareItsBytes) {
  TestServer server(download_config());
  auto client = server.client();
  const std::string id = finished_job(client);
  constexpr size_t kSize = size_t{64} << 20;
  {
    const std::shared_ptr<api::Job> job = server.service().queue().find(id).job;
    ASSERT_TRUE(job);
    std::lock_guard lock(job->mutex);
    job->artifacts.push_back(
        api::make_artifact("large.bin", "application/octet-stream", std::string(kSize, 'x')));
  }
  const size_t before = resident_bytes();
  std::atomic<size_t> peak = before;
  std::atomic<bool> done = false;
  std::thread sampler([&] {
    while (!done) {
      peak = std::max(peak.load(), resident_bytes());
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  constexpr int kRequests = 16;
  std::vector<size_t> received(kRequests, 0);
  std::vector<int> status(kRequests, 0);
  std::vector<std::thread> downloads;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kRequests; ++i)
    downloads.emplace_back([&, i] {
      auto c = server.client();
      // Counted, not kept: the client's copies would hide the server's.
      auto got = c.Get(("/v1/jobs/" + id + "/artifacts/large.bin").c_str(),
                       [&](const char* data, size_t length) {
                         received[i] += length;
                         return data != nullptr;
                       });
      status[i] = got ? got->status : -1;
    });
  for (auto& d : downloads) d.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  done = true;
  sampler.join();
  const size_t growth = peak > before ? peak - before : 0;
  for (int i = 0; i < kRequests; ++i) {
    EXPECT_EQ(status[i], 200) << i;
    EXPECT_EQ(received[i], kSize) << i;
  }
  std::printf("16 parallel GETs of 64 MB: RSS %zu MB before, peak growth %.1f MB, %.2f s\n",
              before >> 20, static_cast<double>(growth) / (1 << 20), seconds);
  EXPECT_LT(growth, kSize / 2) << "RSS grew by " << growth << " bytes";
}

// Parallel first requests of sphere.gltf get the same bytes, converted once: the job
// keeps one view, counted once in the store's result bytes, and later requests get it.
TEST(Downloads, TheGltfViewIsBuiltOnceAndKeptWithTheJob) {
  TestServer server(download_config());
  auto client = server.client();
  const std::string id = finished_job(client);
  const std::shared_ptr<api::Job> job = server.service().queue().find(id).job;
  ASSERT_TRUE(job);
  const size_t results_before = server.service().queue().counts().result_bytes;
  const std::string path = "/v1/jobs/" + id + "/artifacts/sphere.gltf";
  std::vector<std::string> bodies(8);
  std::vector<std::thread> requests;
  for (size_t i = 0; i < bodies.size(); ++i)
    requests.emplace_back([&, i] {
      auto c = server.client();
      auto got = c.Get(path.c_str());
      if (got && got->status == 200) bodies[i] = got->body;
    });
  for (auto& r : requests) r.join();
  api::SharedBytes view;
  {
    std::lock_guard lock(job->mutex);
    ASSERT_EQ(job->gltf_views.size(), 1u);
    view = job->gltf_views.at("sphere.glb");
  }
  ASSERT_TRUE(view);
  for (const std::string& body : bodies) EXPECT_EQ(body, *view);
  auto glb = client.Get(("/v1/jobs/" + id + "/artifacts/sphere.glb").c_str());
  EXPECT_EQ(*view, glb_to_gltf(glb->body));
  auto again = client.Get(path.c_str());
  EXPECT_EQ(again->body, *view);
  EXPECT_EQ(again->get_header_value("Content-Type"), "model/gltf+json");
  {
    std::lock_guard lock(job->mutex);
    EXPECT_EQ(job->gltf_views.at("sphere.glb"), view);  // the same object: not rebuilt
  }
  EXPECT_EQ(server.service().queue().counts().result_bytes, results_before + view->size());
  // A range of the view is a range of its bytes.
  auto range = client.Get(path.c_str(), {{"Range", "bytes=10-19"}});
  EXPECT_EQ(range->status, 206);
  EXPECT_EQ(range->body, view->substr(10, 10));
  // Deleting the job gives back its artifacts and its view.
  EXPECT_EQ(client.Delete(("/v1/jobs/" + id).c_str())->status, 204);
  EXPECT_EQ(server.service().queue().counts().result_bytes, 0u);
}

// Redis mode's downloads: requests for one key while it loads share that one load.
TEST(Downloads, TheCacheLoadsAKeyOnceForParallelRequests) {
  server::SharedBytesCache cache(1000);
  std::atomic<int> loads = 0;
  std::vector<api::SharedBytes> got(16);
  std::vector<std::thread> requests;
  for (size_t i = 0; i < got.size(); ++i)
    requests.emplace_back([&, i] {
      got[i] = cache.get("job/sphere.glb", [&] {
        ++loads;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        return api::share_bytes(std::string(600, 'g'));
      });
    });
  for (auto& r : requests) r.join();
  EXPECT_EQ(loads, 1);
  for (const auto& g : got) EXPECT_EQ(g, got[0]);
  EXPECT_EQ(cache.kept_bytes(), 600u);
  // Another key over the capacity pushes the least recently used out.
  cache.get("job/other.glb", [] { return api::share_bytes(std::string(500, 'o')); });
  EXPECT_EQ(cache.kept_bytes(), 500u);
  // Larger than the capacity: shared with its requests, not kept.
  EXPECT_EQ(cache.get("job/huge", [] { return api::share_bytes(std::string(2000, 'h')); })->size(),
            2000u);
  EXPECT_EQ(cache.kept_bytes(), 500u);
  // A failed load reaches its request and is not kept.
  EXPECT_THROW(cache.get("job/bad", []() -> api::SharedBytes { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_EQ(cache.get("job/bad", [] { return api::share_bytes("ok"); })->size(), 2u);
}

}  // namespace
}  // namespace spheremap
