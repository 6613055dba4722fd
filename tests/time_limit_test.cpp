// The time limit and cancel as behaviour, not wall time (timed tests are flaky under
// load; the overruns measured on large meshes are in BENCHMARKS.md): a stopped map is
// complete, its verdict is time_limit (or cancelled), and it names the stage that was
// running; the hierarchy itself can be stopped.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>

#include "core/map/certification.h"
#include "core/map/hierarchy.h"
#include "core/map/pipeline.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

TEST(TimeLimit, ALimitAlreadyPassedStopsInTheHierarchyWithACompleteMap) {
  const PolygonMesh mesh = testing::icosphere(4);
  MapOptions options;
  options.time_limit_seconds = 10;
  MapControl control;
  control.clock_start = std::chrono::steady_clock::now() - std::chrono::hours(1);
  const MappedMesh mapped = map_mesh(mesh, {}, options, control);
  EXPECT_EQ(mapped.map.stop_reason, StopReason::kTimeLimit);
  EXPECT_EQ(mapped.map.stopped_in, "hierarchy");
  EXPECT_EQ(mapped.map.sphere.size(), mesh.vertex_count());
  const Certification verdict = certify(mapped, mapped.float32_check);
  EXPECT_FALSE(verdict.certified);
  EXPECT_EQ(verdict.problem, "time_limit");
  EXPECT_NE(verdict.detail.find("during its hierarchy stage"), std::string::npos) << verdict.detail;
}

TEST(TimeLimit, ACancelNamesTheStageThatWasRunning) {
  std::atomic<bool> cancel = false;
  MapControl control;
  control.cancel = &cancel;
  control.on_progress = [&](const MapProgress& p) {
    if (p.stage == "optimize" && p.level == 3) cancel = true;
  };
  const MapResult result = map_to_sphere(testing::icosphere(4), {}, control);
  EXPECT_EQ(result.stop_reason, StopReason::kCancelled);
  EXPECT_EQ(result.stopped_in, "optimize");
}

TEST(TimeLimit, AMapThatRunsToTheEndNamesNoStage) {
  const MapResult result = map_to_sphere(testing::icosphere(2), {});
  EXPECT_EQ(result.stop_reason, StopReason::kBijective);
  EXPECT_EQ(result.stopped_in, "");
}

TEST(TimeLimit, TheHierarchyStopsWhenAsked) {
  const PolygonMesh mesh = testing::icosphere(5);  // 10,242 vertices: several questions
  const std::vector<Triangle> triangles = fan_triangulate(mesh).triangles;
  int asked = 0;
  const std::function<bool()> stop_at_third = [&] { return ++asked == 3; };
  EXPECT_THROW(build_hierarchy(mesh.positions, triangles, 2.0, stop_at_third), HierarchyStopped);
  EXPECT_EQ(asked, 3);
  const std::function<bool()> never = [] { return false; };
  EXPECT_EQ(build_hierarchy(mesh.positions, triangles, 2.0, never).level_sizes.back(),
            mesh.vertex_count());
}

}  // namespace
}  // namespace spheremap
