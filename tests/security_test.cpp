// The service against inputs that multiply its work or memory by references (security
// findings "Security III"): images named many times are held, sent to the worker and
// written once; resources past the cap are 413; a reader stops inside the glTF at the
// intake deadline; an allocation failure fails one job, never the process.
#include <gtest/gtest.h>

#include <new>
#include <set>
#include <stdexcept>

#include "api/job_request.h"
#include "api/problem.h"
#include "core/io/glb_writer.h"
#include "core/io/jpeg_scans.h"
#include "server/job_guard.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"
#include "tests/test_server.h"

namespace spheremap {
namespace {

using nlohmann::json;

server::ServerConfig security_config() {
  server::ServerConfig config;
  config.workers = 1;
  config.threads_per_job = 1;
  config.http_threads = 4;
  config.worker_executable = SPHEREMAP_BINARY;  // this test binary is not spheremap
  return config;
}

json wait_done(httplib::Client& client, const std::string& id) {
  json job;
  for (int i = 0; i < 6000; ++i) {
    auto result = client.Get(("/v1/jobs/" + id).c_str());
    if (!result || result->status != 200) return json{{"status", "lost"}};
    job = json::parse(result->body);
    if (job["status"] != "queued" && job["status"] != "running") return job;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return job;
}

TEST(ServiceSecurity, ImagesNamingOneViewReachTheWorkerAndTheSphereOnce) {
  testing::TestServer server(security_config());
  auto client = server.client();
  const std::string glb = testing::many_images_naming_one_view(256 << 10, 480);
  auto submitted = client.Post("/v1/jobs", glb, "model/gltf-binary");
  ASSERT_TRUE(submitted);
  ASSERT_EQ(submitted->status, 202) << submitted->body;
  const json done = wait_done(client, json::parse(submitted->body)["id"]);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  auto sphere = client.Get(done["artifacts"]["sphere.glb"]["href"].get<std::string>().c_str());
  ASSERT_TRUE(sphere);
  ASSERT_EQ(sphere->status, 200);
  EXPECT_LT(sphere->body.size(), glb.size() + (64u << 10));  // not 480 x 256 KB
  const testing::Glb written(sphere->body);
  std::set<size_t> views;
  for (const auto& image : written.json["images"]) views.insert(image["bufferView"].get<size_t>());
  EXPECT_EQ(written.json["images"].size(), 481u);
  EXPECT_EQ(views.size(), 2u);
}

TEST(ServiceSecurity, ResourcesOverTheCapAre413) {
  server::ServerConfig config = security_config();
  config.max_resource_bytes = 128 << 10;
  testing::TestServer server(config);
  auto client = server.client();
  auto answer = client.Post("/v1/jobs", testing::many_images_naming_one_view(256 << 10, 2),
                            "model/gltf-binary");
  ASSERT_TRUE(answer);
  EXPECT_EQ(answer->status, 413) << answer->body;
  EXPECT_NE(answer->body.find("131072"), std::string::npos) << answer->body;  // the cap
  // The server goes on.
  EXPECT_EQ(client.Get("/healthz")->status, 200);
}

// A base-colour JPEG of more scans than the decoder is allowed (core/io/jpeg_scans.h) is
// refused when a remesh is submitted, not found out by the job's colour bake.
TEST(ServiceSecurity, ARemeshWhoseJpegHasTooManyScansIs422) {
  testing::TestServer server(security_config());
  auto client = server.client();
  std::string jpeg = "\xff\xd8";
  for (size_t i = 0; i <= kMaxJpegScans; ++i) jpeg += std::string("\xff\xda\x00\x02", 4);
  jpeg += "\xff\xd9";
  const PolygonMesh mesh = testing::horseshoe();
  GlbMesh glb;
  glb.positions = mesh.positions;
  glb.triangles = fan_triangulate(mesh).triangles;
  glb.texcoords.assign(mesh.positions.size(), {0.5f, 0.5f});
  glb.base_color_png = jpeg;  // typed by its bytes when read: a JPEG
  glb.material_name = "many scans";
  auto remesh = client.Post("/v1/jobs?outputs=remesh", format_glb(glb), "model/gltf-binary");
  ASSERT_TRUE(remesh);
  EXPECT_EQ(remesh->status, 422) << remesh->body;
  EXPECT_EQ(json::parse(remesh->body)["check"], "jpeg_scans") << remesh->body;
}

TEST(ServiceSecurity, ARemeshWhoseTexturesExceedMaxImagePixelsIs413) {
  server::ServerConfig config = security_config();
  config.max_image_pixels = 100;  // the test texture has 16 x 16
  testing::TestServer server(config);
  auto client = server.client();
  const std::string glb = testing::textured_glb(testing::horseshoe());
  auto remesh = client.Post("/v1/jobs?outputs=remesh", glb, "model/gltf-binary");
  ASSERT_TRUE(remesh);
  EXPECT_EQ(remesh->status, 413) << remesh->body;
  EXPECT_EQ(json::parse(remesh->body)["check"], "image_pixels");
  EXPECT_NE(remesh->body.find("256 pixels"), std::string::npos) << remesh->body;
  auto sphere = client.Post("/v1/jobs", glb, "model/gltf-binary");  // no bake: accepted
  ASSERT_TRUE(sphere);
  EXPECT_EQ(sphere->status, 202) << sphere->body;
}

TEST(ServiceSecurity, TheReaderStopsInsideTheGltfAtTheDeadline) {
  httplib::Request request;
  request.set_header("Content-Type", "model/gltf-binary");
  request.body = testing::primitives_naming_one_big_accessor(20000, 4);
  const api::IntakeDeadline passed(api::IntakeDeadline::Clock::now(), 0.1);
  try {
    api::read_job_request(request, api::ApiSettings{}, passed);
    FAIL() << "expected 503 intake_timeout";
  } catch (const api::Problem& p) {
    EXPECT_EQ(p.status, 503);
    EXPECT_EQ(p.slug, "intake_timeout");
    // Stopped by the reader's own question, not at the stage boundary after it.
    EXPECT_NE(std::string(p.what()).find("part of the glTF"), std::string::npos) << p.what();
  }
}

TEST(ServiceSecurity, AnAllocationFailureFailsTheJobNotTheProcess) {
  api::Job job;
  job.artifacts.push_back(api::make_artifact("sphere.glb", "model/gltf-binary", "partial"));
  const api::JobStatus status =
      server::run_guarded(job, []() -> api::JobStatus { throw std::bad_alloc(); });
  EXPECT_EQ(status, api::JobStatus::kFailed);
  ASSERT_TRUE(job.error);
  EXPECT_EQ(job.error->problem, "out_of_memory");
  EXPECT_EQ(job.error->status, 507);
  EXPECT_TRUE(job.artifacts.empty());  // a partial answer is never served

  api::Job other;
  EXPECT_EQ(server::run_guarded(other, []() -> api::JobStatus { throw std::logic_error("x"); }),
            api::JobStatus::kFailed);
  ASSERT_TRUE(other.error);
  EXPECT_EQ(other.error->problem, "internal");
  api::Job fine;
  EXPECT_EQ(server::run_guarded(fine, [] { return api::JobStatus::kSucceeded; }),
            api::JobStatus::kSucceeded);
  EXPECT_FALSE(fine.error);
}

}  // namespace
}  // namespace spheremap
