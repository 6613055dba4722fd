// The octahedral frame of a remesh: candidates are proper rotations, the decoded point turns
// with the frame, and the choice puts the square's dense sampling where the map squeezed
// the surface, which brings the remesh nearer to it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/map/pipeline.h"
#include "core/mesh/surface_distance.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/octahedral_frame_choice.h"
#include "core/outputs/remesh.h"
#include "core/outputs/report_json.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

double l1(const Vec3& d) {
  return std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
}

TEST(OctahedralFrame, CandidatesAreDistinctProperRotations) {
  for (int k = 0; k < kFrameCandidates; ++k) {
    const OctahedralFrame f = frame_candidate(k);
    const auto& r = f.rotation;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;
        for (int m = 0; m < 3; ++m) dot += r[i][m] * r[j][m];
        EXPECT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12) << k;
      }
    const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                       r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                       r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    EXPECT_NEAR(det, 1.0, 1e-12) << k;
    EXPECT_FALSE(f.identity()) << k;
    // The decoded point turns with the frame, and back.
    const Vec2 s{0.3, -0.55};
    const Vec3 turned = octahedral_decode(s, f);
    EXPECT_NEAR(norm(turned - f.to_sphere(octahedral_decode(s))), 0, 1e-15);
    EXPECT_NEAR(norm(f.from_sphere(turned) - octahedral_decode(s)), 0, 1e-14);
    for (int other = 0; other < k; ++other) {
      const OctahedralFrame g = frame_candidate(other);
      double difference = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) difference += std::abs(r[i][j] - g.rotation[i][j]);
      EXPECT_GT(difference, 0.1) << k << " " << other;
    }
  }
  EXPECT_TRUE(OctahedralFrame{}.identity());
}

// A sphere whose surface rises into a narrow spike over a face centre of the octahedron
// (where the unturned square samples the sphere most sparsely): the map gives the spike
// little of the sphere, so a coarse remesh cuts across it.
struct SpikedSphere {
  PolygonMesh sphere = testing::icosphere(5);
  std::vector<Triangle> triangles = fan_triangulate(sphere).triangles;
  Vec3 spike = Vec3{1, 1, 1} * (1 / std::sqrt(3.0));
  std::vector<Vec3> surface;
  SpikedSphere() {
    for (const Vec3& q : sphere.positions)
      surface.push_back(q * (1 + 2 * std::exp(-squared_norm(q - spike) / 0.02)));
  }
};

TEST(OctahedralFrameChoice, TurnsTheDenseSamplingOntoWhatTheMapSqueezed) {
  const SpikedSphere s;
  const FrameChoice choice = choose_octahedral_frame(s.surface, s.sphere.positions, s.triangles);
  EXPECT_LT(choice.predicted_largest, 0.8 * choice.unturned_largest);
  // The spike's direction in the square's frame is near one of the octahedron's vertices
  // (|d|_1 = 1 there, sqrt 3 at a face centre).
  EXPECT_LT(l1(choice.frame.from_sphere(s.spike)), 1.25);
  EXPECT_NEAR(l1(OctahedralFrame{}.from_sphere(s.spike)), std::sqrt(3.0), 1e-12);

  // Measured: the remesh over the chosen frame is nearer the spiked surface.
  const auto hausdorff = [&](const OctahedralFrame& frame) {
    const OctahedralRemesh remesh =
        octahedral_remesh(s.surface, s.sphere.positions, s.triangles, 16, 1, nullptr, frame);
    EXPECT_EQ(remesh.unlocated, 0u);
    return surface_distance(s.surface, s.triangles, remesh.positions, remesh.triangles, 1)
        .hausdorff;
  };
  const double unturned = hausdorff(OctahedralFrame{}), turned = hausdorff(choice.frame);
  EXPECT_LT(turned, 0.8 * unturned) << turned << " " << unturned;
}

// Each prediction ranks every candidate (the remesh screens the best few of both). With
// one error, at the spike, the predicted error grows with |d|_1 of the spike in the frame
// (1 at an octahedron vertex, where the square samples densest), so the ranking is that
// order; from the map's areas the spike (a small patch, not one direction) sets it within
// a percent.
TEST(OctahedralFrameChoice, RanksEveryCandidateBestFirst) {
  const SpikedSphere s;
  const auto spike_l1 = [&](int k) { return l1(frame_candidate(k).from_sphere(s.spike)); };
  const std::vector<SampledError> at_spike = {{s.spike, 0.1}};
  const FrameChoice by_error = choose_octahedral_frame(at_spike, OctahedralFrame{});
  const FrameChoice by_area = choose_octahedral_frame(s.surface, s.sphere.positions, s.triangles);
  for (const FrameChoice* choice : {&by_error, &by_area}) {
    ASSERT_EQ(choice->ranked.size(), static_cast<size_t>(kFrameCandidates));
    std::vector<int> sorted = choice->ranked;
    std::sort(sorted.begin(), sorted.end());
    for (int k = 0; k < kFrameCandidates; ++k) EXPECT_EQ(sorted[static_cast<size_t>(k)], k);
    EXPECT_TRUE(frame_candidate(choice->ranked.front()) == choice->frame);
    const double slack = choice == &by_error ? 1e-12 : 0.01;
    for (size_t r = 1; r < choice->ranked.size(); ++r)
      EXPECT_LE(spike_l1(choice->ranked[r - 1]), spike_l1(choice->ranked[r]) * (1 + slack)) << r;
  }
  // Screened and measured frames: all up to 128 quads per side, fewer above, one from 512.
  EXPECT_EQ(frames_tried(kFramesScreened, 64), kFramesScreened);
  EXPECT_EQ(frames_tried(kFramesScreened, 128), kFramesScreened);
  EXPECT_EQ(frames_tried(kFramesScreened, 256), kFramesScreened / 4);
  EXPECT_EQ(frames_tried(kFramesMeasured, 256), 1u);
  EXPECT_EQ(frames_tried(kFramesScreened, 512), 1u);
  EXPECT_EQ(frames_tried(kFramesScreened, 4096), 1u);
}

// The errors of a remesh say where it is off: on the spiked sphere's unturned remesh the
// largest lies at the spike, and the frame chosen from them puts the spike where the
// square samples densely; the remesh there is nearer.
TEST(OctahedralFrameChoice, FromARemeshsErrorsTurnsTheDenseSamplingOntoTheWorstSpot) {
  const SpikedSphere s;
  const OctahedralRemesh unturned =
      octahedral_remesh(s.surface, s.sphere.positions, s.triangles, 16, 1, nullptr, {});
  const std::vector<SampledError> errors = sampled_errors(
      SurfaceMeasure(s.surface, s.triangles), s.surface, s.sphere.positions, unturned, 1, nullptr);
  ASSERT_EQ(errors.size(), unturned.triangles.size() + s.surface.size());
  const SampledError worst = *std::max_element(errors.begin(), errors.end(),
                                               [](auto& a, auto& b) { return a.error < b.error; });
  EXPECT_GT(dot(worst.direction, s.spike), 0.95);
  // A frame's screen needs only the largest error: the same, bit for bit, on any threads.
  double largest = 0;
  for (const SampledError& e : errors) largest = std::max(largest, e.error);
  for (int threads : {1, 2})
    EXPECT_EQ(largest_sampled_error(SurfaceMeasure(s.surface, s.triangles), s.surface, unturned,
                                    threads, nullptr),
              largest);
  const FrameChoice choice = choose_octahedral_frame(errors, unturned.frame);
  EXPECT_LT(choice.predicted_largest, 0.8 * choice.unturned_largest);
  EXPECT_LT(l1(choice.frame.from_sphere(s.spike)), 1.25);
  const OctahedralRemesh turned =
      octahedral_remesh(s.surface, s.sphere.positions, s.triangles, 16, 1, nullptr, choice.frame);
  const auto hausdorff = [&](const OctahedralRemesh& r) {
    return surface_distance(s.surface, s.triangles, r.positions, r.triangles, 1).hausdorff;
  };
  EXPECT_LT(hausdorff(turned), 0.8 * hausdorff(unturned));
}

// In an asset of parts, a part tries turned frames only when its remesh stands over
// kFrameTrialDistance of the ASSET's diagonal from it: a small part far off by its own
// diagonal, but near at the asset's scale, keeps its unturned frame; the large one tries.
TEST(OctahedralFrameChoice, AnAssetsPartsTryFramesAtTheAssetsScale) {
  PolygonMesh small = testing::horseshoe();
  for (Vec3& p : small.positions) p = p * 0.02;
  PolygonMesh input = testing::assembled({{testing::horseshoe(), {0, 0, 0}}, {small, {0, 0, 4}}});
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 2u);
  const RemeshAsset asset = remesh_asset(mapped, 16);
  const nlohmann::json& parts = asset.metrics["parts"];
  ASSERT_EQ(parts.size(), 2u);
  const bool first_larger = parts[0]["distance"]["diagonal"].get<double>() >
                            parts[1]["distance"]["diagonal"].get<double>();
  const nlohmann::json& large = parts[first_larger ? 0 : 1];
  const nlohmann::json& little = parts[first_larger ? 1 : 0];
  EXPECT_TRUE(large["octahedral_frame"]["turned_frames_tried"]);
  // Alone, the small part would try: it stands over the threshold by its own diagonal.
  EXPECT_GT(little["octahedral_frame"]["unturned_hausdorff"].get<double>(), kFrameTrialDistance);
  EXPECT_FALSE(little["octahedral_frame"]["turned_frames_tried"]);
  EXPECT_EQ(little["octahedral_frame"]["kept"], "unturned");
}

// Each sample of a turned remesh is the surface at the frame's sphere point of its square
// point; the asset keeps whichever frame measured nearer and says which.
TEST(OctahedralFrameChoice, TheRemeshAssetKeepsTheNearerFrameAndReportsIt) {
  const MappedMesh mapped = map_mesh(testing::horseshoe(), {}, {});
  ASSERT_TRUE(mapped.map.check.bijective);
  const RemeshAsset asset = remesh_asset(mapped, 16);
  const nlohmann::json& frame = asset.metrics["octahedral_frame"];
  EXPECT_TRUE(frame["turned_frames_tried"]);  // a 16 x 16 grid stands far off a horseshoe
  const std::string kept = frame["kept"];
  EXPECT_TRUE(kept == "unturned" || kept == "area" || kept == "errors") << kept;
  EXPECT_EQ(kept == "unturned", frame["rotation"][0][0] == 1.0 && frame["rotation"][1][1] == 1.0);
  EXPECT_LE(asset.metrics["distance"]["hausdorff"].get<double>(),
            frame["unturned_hausdorff"].get<double>());
  ASSERT_EQ(frame["rotation"].size(), 3u);
  // A remesh already near its surface is kept unturned without trying (kFrameTrialDistance).
  const MappedMesh ball = map_mesh(testing::icosphere(3), {}, {});
  ASSERT_TRUE(ball.map.check.bijective);
  const RemeshAsset fine = remesh_asset(ball, 128);
  ASSERT_LE(fine.metrics["distance"]["hausdorff"].get<double>(), kFrameTrialDistance);
  EXPECT_FALSE(fine.metrics["octahedral_frame"]["turned_frames_tried"]);
  EXPECT_EQ(fine.metrics["octahedral_frame"]["kept"], "unturned");

  const SpikedSphere s;
  const FrameChoice choice = choose_octahedral_frame(s.surface, s.sphere.positions, s.triangles);
  const OctahedralRemesh remesh =
      octahedral_remesh(s.surface, s.sphere.positions, s.triangles, 8, 1, nullptr, choice.frame);
  for (size_t k = 0; k < remesh.positions.size(); ++k) {
    const Vec3 q = choice.frame.to_sphere(octahedral_decode(remesh.square[k]));
    // The spiked surface is radial: the sample lies along its sphere point's ray.
    const Vec3 p = remesh.positions[k];
    EXPECT_GT(dot(p * (1 / norm(p)), q), 0.999) << k;
  }
}

}  // namespace
}  // namespace spheremap
