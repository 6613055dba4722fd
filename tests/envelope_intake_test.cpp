// Envelopes are built in the job's worker, not in the intake (PrepareOptions::
// defer_envelopes): submissions that need one are accepted at once, and the intake stays
// free for the next ones, whatever the envelopes cost; the envelope runs under the job's
// time limit, and its memory is charged with the job (job_memory_test for the estimate).
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>
#include <vector>

#include "server/job_runner.h"
#include "tests/mesh_generators.h"
#include "tests/mesh_writers.h"
#include "tests/test_server.h"

namespace spheremap {
namespace {

using nlohmann::json;

json job_of(httplib::Client& client, const std::string& id) {
  return json::parse(client.Get(("/v1/jobs/" + id).c_str())->body);
}

json wait_until_done(httplib::Client& client, const std::string& id) {
  json job;
  for (int i = 0; i < 60000; ++i) {
    job = job_of(client, id);
    if (job["status"] != "queued" && job["status"] != "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return job;
}

server::ServerConfig one_worker_one_intake() {
  server::ServerConfig config;
  config.workers = 1;
  config.threads_per_job = 1;
  config.intake_threads = 1;
  config.http_threads = 8;
  config.worker_executable = SPHEREMAP_BINARY;
  return config;
}

// Envelope jobs submitted together are all accepted while the only worker is held by
// another job, so none of their envelopes can have been built yet: the intake only checked
// their grids. A plain submission is then accepted with them still waiting. Once the worker
// is free, each envelope is built there and maps.
TEST(EnvelopeIntake, SubmissionsNeedingEnvelopesDoNotHoldTheIntake) {
  testing::TestServer server(one_worker_one_intake());
  auto client = server.client();
  // Holds the one worker until cancelled (the paper's loop, no iteration cap).
  auto blocker = client.Post("/v1/jobs?method=paper&max_iterations=1000000&time_limit_seconds=60",
                             testing::binary_stl(testing::horseshoe()), "model/stl");
  ASSERT_EQ(blocker->status, 202) << blocker->body;
  const std::string blocking = json::parse(blocker->body)["id"];

  // Tori wrapped, and a Moebius band, which prepare=auto can only map as its envelope.
  const std::vector<std::string> wrap_paths = {"/v1/jobs?prepare=wrap&wrap_resolution=160",
                                               "/v1/jobs?prepare=auto&wrap_resolution=160",
                                               "/v1/jobs?prepare=wrap&wrap_resolution=200"};
  const std::vector<PolygonMesh> meshes = {
      testing::torus(48, 24), testing::moebius_band(96),
      testing::assembled({{testing::torus(24, 12), {}}, {testing::dome(2), {3, 0, 0}}})};
  std::vector<std::future<httplib::Result>> posts;
  for (size_t k = 0; k < meshes.size(); ++k)
    posts.push_back(std::async(std::launch::async, [&, k] {
      auto own = server.client();
      return own.Post(wrap_paths[k].c_str(), testing::binary_stl(meshes[k]), "model/stl");
    }));
  std::vector<std::string> envelope_jobs;
  for (auto& post : posts) {
    const httplib::Result result = post.get();
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 202) << result->body;
    envelope_jobs.push_back(json::parse(result->body)["id"]);
  }
  auto plain = client.Post("/v1/jobs?prepare=exact", testing::binary_stl(testing::icosphere(2)),
                           "model/stl");
  ASSERT_EQ(plain->status, 202) << plain->body;
  for (const std::string& id : envelope_jobs) EXPECT_EQ(job_of(client, id)["status"], "queued");

  EXPECT_EQ(client.Delete(("/v1/jobs/" + blocking).c_str())->status, 202);
  for (const std::string& id : envelope_jobs) {
    const json done = wait_until_done(client, id);
    ASSERT_EQ(done["status"], "succeeded") << done.dump(2);
    EXPECT_TRUE(done["metrics"]["bijective"]);
    EXPECT_GT(done["metrics"]["preparation"]["envelope_faces"].get<size_t>(), 0u) << done.dump(2);
  }
  const json plain_done = wait_until_done(client, json::parse(plain->body)["id"]);
  EXPECT_EQ(plain_done["status"], "succeeded") << plain_done.dump(2);
}

// The job's time limit stops its envelope, which then fails the job as time_limit.
TEST(EnvelopeIntake, TheJobsTimeLimitStopsTheEnvelope) {
  testing::TestServer server(one_worker_one_intake());
  auto client = server.client();
  auto submitted = client.Post("/v1/jobs?prepare=wrap&wrap_resolution=256&time_limit_seconds=0.01",
                               testing::binary_stl(testing::torus(48, 24)), "model/stl");
  ASSERT_EQ(submitted->status, 202) << submitted->body;
  const json failed = wait_until_done(client, json::parse(submitted->body)["id"]);
  ASSERT_EQ(failed["status"], "failed") << failed.dump(2);
  EXPECT_EQ(failed["error"]["type"], "/v1/problems/time_limit") << failed.dump(2);
  EXPECT_NE(failed["error"]["detail"].get<std::string>().find("envelope"), std::string::npos)
      << failed.dump(2);
}

// The envelope's memory is charged with its job: with a budget that holds a small job but not
// the envelope's grid beside it, the envelope job waits for memory while the other runs,
// and runs once it has ended.
TEST(EnvelopeIntake, TheEnvelopesGridIsChargedAgainstTheMemoryBudget) {
  server::ServerConfig config = one_worker_one_intake();
  config.workers = 2;
  // A small job's estimate is about 17 MB; the torus's envelope at 256 voxels across its
  // diagonal (1.9M voxels) adds about 30 MB to its own.
  config.jobs_memory_bytes = 40u << 20;
  testing::TestServer server(config);
  auto client = server.client();
  auto blocker = client.Post("/v1/jobs?method=paper&max_iterations=1000000&time_limit_seconds=60",
                             testing::binary_stl(testing::horseshoe()), "model/stl");
  ASSERT_EQ(blocker->status, 202) << blocker->body;
  const std::string blocking = json::parse(blocker->body)["id"];
  for (int i = 0; i < 6000 && job_of(client, blocking)["status"] == "queued"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(job_of(client, blocking)["status"], "running");
  auto wrapped = client.Post("/v1/jobs?prepare=wrap&wrap_resolution=256",
                             testing::binary_stl(testing::torus(48, 24)), "model/stl");
  ASSERT_EQ(wrapped->status, 202) << wrapped->body;
  const std::string id = json::parse(wrapped->body)["id"];
  std::string stage;
  for (int i = 0; i < 6000 && stage != "waiting_for_memory"; ++i) {
    stage = job_of(client, id)["progress"]["stage"];
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(stage, "waiting_for_memory");
  EXPECT_EQ(job_of(client, blocking)["status"], "running");
  EXPECT_EQ(client.Delete(("/v1/jobs/" + blocking).c_str())->status, 202);
  const json done = wait_until_done(client, id);
  ASSERT_EQ(done["status"], "succeeded") << done.dump(2);
  EXPECT_EQ(done["metrics"]["preparation"]["method"], "wrap");
}

// An envelope that cannot be made in the worker (here a grid over the cap it was left
// with) fails its job with the reason, the map never starts.
TEST(EnvelopeIntake, AnEnvelopeThatCannotBeMadeFailsItsJob) {
  server::Job job;
  job.spec = std::make_unique<server::JobSpec>();
  server::JobSpec& spec = *job.spec;
  spec.input = testing::torus(24, 12);
  PrepareOptions wrap;
  wrap.method = PrepareMethod::kWrap;
  wrap.defer_envelopes = true;
  spec.prepared = prepare_input(spec.input, nullptr, wrap);
  ASSERT_TRUE(spec.prepared.pending.any());
  spec.prepared.pending.envelope.max_voxels = 4096;
  EXPECT_EQ(server::run_job(job, {300, 1}), server::JobStatus::kFailed);
  ASSERT_TRUE(job.error);
  EXPECT_EQ(job.error->problem, "envelope_size");
  EXPECT_EQ(job.error->title, "Envelope cannot be made");
  EXPECT_NE(job.error->detail.find("4096"), std::string::npos) << job.error->detail;
  EXPECT_TRUE(job.artifacts.empty());
}

}  // namespace
}  // namespace spheremap
