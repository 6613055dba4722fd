// prepare=auto (prepare_mesh.h): every part served, exactly where it can be. Parts that map
// alone are mapped as they are; each other part is replaced by its own envelope; a mesh of
// one part that cannot map is wrapped whole; a mesh that maps is untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/io/gltf_reader.h"
#include "core/map/certification.h"
#include "core/map/map_parts.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/report_json.h"
#include "core/prepare/envelope_plan.h"
#include "core/prepare/prepare_mesh.h"
#include "server/worker_protocol.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using testing::assembled;

PrepareOptions automatic() {
  PrepareOptions options;
  options.method = PrepareMethod::kAuto;
  options.envelope.resolution = 96;  // a coarse grid: the test is about the plumbing
  // The open domes here stand for parts only an envelope maps (SheetDoubling's tests double
  // them).
  options.double_open_sheets = false;
  return options;
}

// A sphere (maps), a torus (maps once its handle is closed) and an open dome (its hole too
// large to fill: wrapped).
PolygonMesh kit() {
  return assembled({{testing::icosphere(2), {0, 0, 0}},
                    {testing::torus(24, 12), {6, 0, 0}},
                    {testing::dome(2), {0, 0, 6}}});
}

TEST(PrepareAuto, MapsThePartsThatMapAndWrapsEachOther) {
  PolygonMesh input = kit();
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic());
  EXPECT_EQ(prepared.preparation.method, PrepareMethod::kAuto);
  EXPECT_EQ(prepared.preparation.decided, "parts+wrap");
  ASSERT_EQ(prepared.parts.size(), 3u);
  EXPECT_EQ(prepared.parts_left_out(), 0u);
  size_t wrapped = 0;
  for (const PartReport& part : prepared.parts) {
    EXPECT_NE(part.welded_vertex, kUnreferenced);
    if (!part.wrapped) continue;
    ++wrapped;
    ASSERT_FALSE(part.wrap_reasons.empty());
    EXPECT_TRUE(part.wrap_reasons.front().check == "genus" ||
                part.wrap_reasons.front().check == "boundary")
        << part.wrap_reasons.front().check;
    EXPECT_GT(part.envelope.faces, 0u);
    // Relative to the whole asset's diagonal: the envelope is near its part.
    EXPECT_GT(part.envelope.hausdorff, 0);
    EXPECT_LT(part.envelope.hausdorff, 0.1);
  }
  EXPECT_EQ(wrapped, 1u);  // the dome; the sphere as it is, the torus with its handle closed
  // The exact parts' input vertices (the torus's with the copies its cut made) still weld to
  // their parts; the wrapped dome's to nothing.
  size_t referenced = 0;
  for (uint32_t w : prepared.welded.input_to_welded) referenced += w != kUnreferenced;
  EXPECT_EQ(referenced, input.vertex_count() - testing::dome(2).vertex_count());

  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 3u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  for (const MappedPart& part : mapped.parts)
    EXPECT_TRUE(certify(part.mapped, part.mapped.float32_check).certified);
  // Reports and maps pair up: the wrapped report is the dome's.
  const nlohmann::json parts = metrics_json(mapped, {})["parts"];
  ASSERT_EQ(parts.size(), 3u);
  for (const nlohmann::json& part : parts) {
    EXPECT_TRUE(part["mapped"].get<bool>());
    EXPECT_TRUE(part["bijective"].get<bool>());
    EXPECT_EQ(part.contains("wrapped"), part["faces"] == testing::dome(2).face_count())
        << part.dump();
  }
  // The sphere in the original layout: the input's faces for the exact part, the envelope
  // for the others; written and checked as written.
  const SphereAsset sphere = parts_sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"].get<bool>()) << sphere.metrics.dump();
}

// The same kit under parts (the dome left out): the torus's handle closed, and the sphere in
// the original layout written and checked as written part by part.
TEST(PrepareAuto, TheKitUnderPartsWritesItsOriginalLayoutSphere) {
  PolygonMesh input = kit();
  PrepareOptions options;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.parts_left_out(), 1u);
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 2u);
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  const SphereAsset sphere = parts_sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"].get<bool>()) << sphere.metrics.dump();
}

// A stray triangle far smaller than the asset's voxel is wrapped on a grid of about 16
// voxels across it grown by the asset's offset, not 16 across the triangle alone (then its
// offset, the asset's, spanned some 180 voxels each way: a ball of millions).
TEST(PrepareAuto, ATinyPartsGridSpansItsOffsetNotItsOwnWidth) {
  PolygonMesh stray;
  stray.positions = {{3, 0, 0}, {3.01, 0, 0}, {3, 0.01, 0}};
  stray.add_face(std::vector<uint32_t>{0, 1, 2});
  PolygonMesh input = assembled({{testing::icosphere(2), {0, 0, 0}}, {stray, {0, 0, 0}}});
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic());
  EXPECT_EQ(prepared.preparation.decided, "parts+wrap");
  ASSERT_EQ(prepared.parts.size(), 2u);
  EXPECT_EQ(prepared.parts_left_out(), 0u);
  const PartReport& tiny = prepared.parts[0].wrapped ? prepared.parts[0] : prepared.parts[1];
  ASSERT_TRUE(tiny.wrapped);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_LE(tiny.envelope.grid[axis], 16 + 2 * kGridPadding + 2);
  // Within about the offset (1.5 of the asset's voxels: 1.6% of its diagonal) of the triangle.
  EXPECT_LT(tiny.envelope.hausdorff, 0.03);
}

// A plane with a fin on every inner edge: one part as read, whose non-manifold edges split
// it into thousands of parts (each fin a sheet of its own, doubled). Those are shards of
// the preparation, not parts of the asset (vcglib's abominevole.off: 48,732 of them, whose
// remesh took over a minute): the asset is wrapped whole.
TEST(PrepareAuto, AMeshThePreparationShattersIsWrappedWhole) {
  constexpr uint32_t kSide = 48;
  PolygonMesh input;
  for (uint32_t y = 0; y < kSide; ++y)
    for (uint32_t x = 0; x < kSide; ++x) input.positions.push_back({double(x), double(y), 0});
  auto add = [&input](uint32_t a, uint32_t b, uint32_t c) {
    input.add_face(std::vector<uint32_t>{a, b, c});
  };
  auto fin = [&](uint32_t a, uint32_t b) {
    const Vec3 top = (input.positions[a] + input.positions[b]) * 0.5 + Vec3{0.1, 0.2, 0.7};
    input.positions.push_back(top);
    add(a, b, static_cast<uint32_t>(input.positions.size() - 1));
  };
  for (uint32_t y = 0; y + 1 < kSide; ++y)
    for (uint32_t x = 0; x + 1 < kSide; ++x) {
      const uint32_t v = y * kSide + x;
      add(v, v + 1, v + kSide + 1);
      add(v, v + kSide + 1, v + kSide);
      fin(v, v + kSide + 1);  // the diagonal, always inner
      if (y > 0) fin(v, v + 1);
      if (x > 0) fin(v, v + kSide);
    }
  PrepareOptions options = automatic();
  options.double_open_sheets = true;  // as by default: each fin a part that maps
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.decided, "wrap");
  EXPECT_TRUE(remaining_failures(prepared).empty());
  EXPECT_GT(prepared.preparation.envelope.faces, 0u);
  EXPECT_EQ(prepared.topology.component_vertices.size(), 1u);
}

TEST(PrepareAuto, OnePartThatCannotMapIsWrappedWhole) {
  PolygonMesh input = testing::dome(2);  // its hole is too large to fill
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic());
  EXPECT_EQ(prepared.preparation.decided, "wrap");
  EXPECT_TRUE(remaining_failures(prepared).empty());
  EXPECT_GT(prepared.preparation.envelope.faces, 0u);
  EXPECT_EQ(input.face_count(), prepared.welded.mesh.face_count());  // the input is the envelope
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  EXPECT_EQ(metrics_json(mapped, {})["preparation"]["decided"], "wrap");
}

// A CAD export's patch stored a float apart from the rest (its corners twice, 2e-7 of the
// diagonal apart): a torus with a hole too large to fill beside a loose disc, which mapped
// only with the torus wrapped. Auto welds at the smallest tolerance that closes it first,
// says which, and maps the torus as it is.
TEST(PrepareAuto, WeldsASeamAFloatApartBeforeItWrapsAnything) {
  PolygonMesh input = testing::torus(12, 24);
  const double diagonal = std::sqrt(6.0 * 6 + 6 * 6 + 2 * 2);
  std::map<uint32_t, uint32_t> copy;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i)  // face j * 12 + i: a 6 x 5 patch, a tenth of the torus
      for (uint32_t k = input.offsets[j * 12 + i]; k < input.offsets[j * 12 + i + 1]; ++k) {
        const uint32_t v = input.indices[k];
        const auto [it, added] = copy.emplace(v, uint32_t(input.positions.size()));
        if (added) input.positions.push_back(input.positions[v] + Vec3{2e-7 * diagonal, 0, 0});
        input.indices[k] = it->second;
      }
  PrepareOptions options;
  options.method = PrepareMethod::kAuto;
  PolygonMesh as_given = input;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.weld_tolerance, 1e-6);
  EXPECT_EQ(prepared.preparation.decided, "repair");
  EXPECT_EQ(prepared.original, nullptr);
  EXPECT_TRUE(prepared.parts.empty());  // one part again, nothing wrapped
  EXPECT_EQ(metrics_json(map_prepared(prepared, {}), {})["preparation"]["weld_tolerance"], 1e-6);

  // Without it the torus is a part only an envelope maps; an input with nothing a weld
  // closes keeps the exact weld.
  options.weld_tolerance = 0;
  PrepareOptions parts = options;
  parts.method = PrepareMethod::kParts;
  EXPECT_FALSE(input_failures(prepare_input(as_given, nullptr, parts)).empty());
  PolygonMesh torus = testing::torus(12, 24);
  EXPECT_EQ(prepare_input(torus, nullptr, options).preparation.weld_tolerance, 0);
}

TEST(PrepareAuto, AMeshThatMapsIsUntouched) {
  PolygonMesh input = testing::icosphere(3), same = input;
  const PreparedMesh automatic_prepared = prepare_input(input, nullptr, automatic());
  EXPECT_EQ(automatic_prepared.preparation.decided, "exact");
  const PreparedMesh parts = prepare_input(same, nullptr, {});
  const MappedMesh a = map_prepared(automatic_prepared, {}), b = map_prepared(parts, {});
  EXPECT_EQ(a.map.sphere, b.map.sphere);
}

// The report's top level is the mesh that is mapped; "input" is the file as read. A torus
// whose handle is capped maps as genus 0, but the report must still say it is a torus.
TEST(PrepareAuto, TheReportSaysWhatTheInputWasBesideWhatIsMapped) {
  PolygonMesh torus = testing::torus(16, 12);
  const size_t torus_faces = torus.face_count();
  const nlohmann::json capped = topology_json(prepare_input(torus, nullptr, automatic()));
  EXPECT_EQ(capped["preparation"]["decided"], "repair");
  EXPECT_EQ(capped["genus"], 0);
  EXPECT_EQ(capped["input"]["genus"], 1);
  EXPECT_EQ(capped["input"]["euler_characteristic"], 0);
  EXPECT_EQ(capped["input"]["faces"], torus_faces);
  EXPECT_GT(capped["faces"].get<size_t>(), torus_faces);  // the caps' faces

  PolygonMesh dome = testing::dome(2);  // wrapped whole: "input" is the dome, not its envelope
  const size_t dome_faces = dome.face_count();
  const nlohmann::json wrapped = topology_json(prepare_input(dome, nullptr, automatic()));
  EXPECT_EQ(wrapped["preparation"]["decided"], "wrap");
  EXPECT_EQ(wrapped["input"]["faces"], dome_faces);
  EXPECT_EQ(wrapped["input"]["closed"], false);
  EXPECT_EQ(wrapped["input"]["boundary_loops"], 1);
  EXPECT_EQ(wrapped["closed"], true);
  EXPECT_NE(wrapped["faces"], dome_faces);

  PolygonMesh forced = testing::dome(2);  // the same under --prepare wrap
  PrepareOptions wrap = automatic();
  wrap.method = PrepareMethod::kWrap;
  const nlohmann::json wrapped_forced = topology_json(prepare_input(forced, nullptr, wrap));
  EXPECT_EQ(wrapped_forced["input"]["faces"], dome_faces);
  EXPECT_EQ(wrapped_forced["input"]["boundary_loops"], 1);
}

// A scatter of many fragments (here 100 separate triangles) is wrapped as one envelope,
// not part by part.
TEST(PrepareAuto, ManyFragmentsAreWrappedAsOne) {
  std::vector<std::pair<PolygonMesh, Vec3>> pieces;
  PolygonMesh triangle;
  triangle.positions = {{0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}};
  triangle.add_face(std::vector<uint32_t>{0, 1, 2});
  // Past kMaxWrappedParts (256) that do not map.
  for (int k = 0; k < 300; ++k) pieces.push_back({triangle, {double(k % 20), double(k / 20), 0}});
  PolygonMesh input = assembled(pieces);
  const PreparedMesh prepared = prepare_input(input, nullptr, automatic());
  EXPECT_EQ(prepared.preparation.decided, "wrap");
  EXPECT_TRUE(remaining_failures(prepared).empty());
}

// The wrapped parts' reports cross the worker pipe whole.
TEST(PrepareAuto, WrappedPartsCrossTheWorkerProtocol) {
  api::JobSpec spec;
  spec.input = kit();
  spec.prepared = prepare_input(spec.input, nullptr, automatic());
  const server::WorkerRequest back = server::decode_request(server::encode_request(spec, 10, 1));
  const PreparedMesh& got = back.spec.prepared;
  EXPECT_EQ(got.preparation.decided, "parts+wrap");
  ASSERT_EQ(got.parts.size(), spec.prepared.parts.size());
  for (size_t k = 0; k < got.parts.size(); ++k) {
    EXPECT_EQ(got.parts[k].wrapped, spec.prepared.parts[k].wrapped);
    EXPECT_EQ(got.parts[k].welded_vertex, spec.prepared.parts[k].welded_vertex);
    EXPECT_EQ(got.parts[k].envelope.faces, spec.prepared.parts[k].envelope.faces);
    EXPECT_EQ(got.parts[k].envelope.hausdorff, spec.prepared.parts[k].envelope.hausdorff);
    EXPECT_EQ(got.parts[k].wrap_reasons.size(), spec.prepared.parts[k].wrap_reasons.size());
    EXPECT_EQ(got.parts[k].original_faces, spec.prepared.parts[k].original_faces);
  }
}

// A wrapped whole's original (the input it stands for) crosses the pipe too.
TEST(PrepareAuto, AWrappedWholesOriginalCrossesTheWorkerProtocol) {
  api::JobSpec spec;
  spec.input = testing::dome(2);
  const size_t dome_faces = spec.input.face_count();
  spec.prepared = prepare_input(spec.input, nullptr, automatic());
  ASSERT_EQ(spec.prepared.preparation.decided, "wrap");
  ASSERT_TRUE(spec.prepared.original);
  const server::WorkerRequest back = server::decode_request(server::encode_request(spec, 10, 1));
  ASSERT_TRUE(back.spec.prepared.original);
  EXPECT_EQ(back.spec.prepared.original->mesh.face_count(), dome_faces);
  EXPECT_EQ(back.spec.prepared.original->mesh.positions, spec.prepared.original->mesh.positions);
}

// The triangles a fill added (weighed down by the map) and its new vertices' count cross
// the pipe; a corner that is not a vertex of the mesh is refused, not looked up.
TEST(PrepareAuto, FilledTrianglesCrossTheWorkerProtocol) {
  api::JobSpec spec;
  const PolygonMesh capped = testing::capped_tube(32, 24, 3);
  spec.input.positions = capped.positions;
  for (size_t f = 0; f + 1 < capped.face_count(); ++f) spec.input.add_face(capped.face(f));
  PrepareOptions options;
  options.method = PrepareMethod::kRepair;
  options.max_hole_fill = 1;
  spec.prepared = prepare_input(spec.input, nullptr, options);
  ASSERT_EQ(spec.prepared.preparation.holes_filled, 1u);
  ASSERT_FALSE(spec.prepared.filled.empty());
  ASSERT_GT(spec.prepared.preparation.vertices_added, 0u);
  const server::WorkerRequest back = server::decode_request(server::encode_request(spec, 10, 1));
  EXPECT_EQ(back.spec.prepared.filled, spec.prepared.filled);
  EXPECT_EQ(back.spec.prepared.preparation.vertices_added,
            spec.prepared.preparation.vertices_added);
  spec.prepared.filled.back()[1] = static_cast<uint32_t>(spec.prepared.welded.mesh.vertex_count());
  EXPECT_THROW(server::decode_request(server::encode_request(spec, 10, 1)), std::runtime_error);
}

// Under defer_envelopes (the server's intake) nothing is wrapped yet; what build_envelopes
// makes of it after the worker protocol is what prepare_input makes at once.
void expect_deferred_same_as_eager(const PolygonMesh& mesh, PrepareOptions options) {
  PolygonMesh eager_input = mesh;
  const PreparedMesh eager = prepare_input(eager_input, nullptr, options);
  options.defer_envelopes = true;
  api::JobSpec spec;
  spec.input = mesh;
  spec.prepared = prepare_input(spec.input, nullptr, options);
  ASSERT_TRUE(spec.prepared.pending.any());
  EXPECT_FALSE(spec.prepared.original);
  EXPECT_TRUE(std::none_of(spec.prepared.parts.begin(), spec.prepared.parts.end(),
                           [](const PartReport& p) { return p.wrapped; }));
  EXPECT_GT(spec.prepared.pending.grid_voxels, 0u);
  server::WorkerRequest back = server::decode_request(server::encode_request(spec, 10, 1));
  PreparedMesh& got = back.spec.prepared;
  ASSERT_EQ(got.pending.method, options.method);
  EXPECT_EQ(got.pending.parts, spec.prepared.pending.parts);
  EXPECT_EQ(got.pending.grid_voxels, spec.prepared.pending.grid_voxels);
  build_envelopes(got, back.spec.input, &back.spec.look, {});
  EXPECT_FALSE(got.pending.any());
  EXPECT_EQ(got.preparation.method, eager.preparation.method);
  EXPECT_EQ(got.preparation.decided, eager.preparation.decided);
  EXPECT_EQ(got.preparation.envelope.faces, eager.preparation.envelope.faces);
  EXPECT_EQ(got.welded.mesh.positions, eager.welded.mesh.positions);
  EXPECT_EQ(got.welded.mesh.indices, eager.welded.mesh.indices);
  EXPECT_EQ(got.welded.input_to_welded, eager.welded.input_to_welded);
  EXPECT_EQ(got.filled, eager.filled);
  EXPECT_EQ(back.spec.input.positions, eager_input.positions);
  EXPECT_EQ(bool(got.original), bool(eager.original));
  ASSERT_EQ(got.parts.size(), eager.parts.size());
  for (size_t k = 0; k < got.parts.size(); ++k) {
    EXPECT_EQ(got.parts[k].wrapped, eager.parts[k].wrapped);
    EXPECT_EQ(got.parts[k].welded_vertex, eager.parts[k].welded_vertex);
    EXPECT_EQ(got.parts[k].original_faces, eager.parts[k].original_faces);
  }
  EXPECT_TRUE(remaining_failures(got).empty());
}

TEST(PrepareAuto, DeferredPartEnvelopesMatchTheEagerOnes) {
  expect_deferred_same_as_eager(kit(), automatic());
}

TEST(PrepareAuto, ADeferredWholeEnvelopeMatchesTheEagerOne) {
  expect_deferred_same_as_eager(testing::dome(2), automatic());
  PrepareOptions wrap = automatic();
  wrap.method = PrepareMethod::kWrap;
  expect_deferred_same_as_eager(kit(), wrap);
}

// The intake still refuses at once what no envelope can be made of (the grid over its cap),
// and leaves nothing pending for a mesh that maps.
TEST(PrepareAuto, DeferringChecksTheGridAndLeavesMappableMeshesAlone) {
  PrepareOptions options = automatic();
  options.defer_envelopes = true;
  options.method = PrepareMethod::kWrap;
  options.envelope.max_voxels = 4096;
  PolygonMesh torus = testing::torus(24, 12);
  try {
    prepare_input(torus, nullptr, options);
    ADD_FAILURE() << "a grid over max_voxels was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "envelope_size");
  }
  options.method = PrepareMethod::kAuto;
  PolygonMesh sphere = testing::icosphere(2);
  EXPECT_FALSE(prepare_input(sphere, nullptr, options).pending.any());
}

// The whole's grid over the cap: the intake leaves the parts' envelopes to the worker when
// each part's own grid fits, and refuses at once (nothing pending, the part left out) when
// one does not, as the eager path would: the job must not be accepted only to fail.
TEST(PrepareAuto, AWholeOverTheCapIsAcceptedOnlyWhenEveryPartFits) {
  auto input = [] {
    return assembled({{testing::dome(2), {0, 0, 0}}, {testing::icosphere(2), {12, 0, 0}}});
  };
  PrepareOptions options = automatic();
  options.defer_envelopes = true;
  PolygonMesh whole = input();
  options.envelope.max_voxels = plan_envelope(whole, options.envelope).grid.size() - 1;
  PreparedMesh accepted = prepare_input(whole, nullptr, options);
  ASSERT_TRUE(accepted.pending.any());
  EXPECT_TRUE(accepted.pending.parts);
  build_envelopes(accepted, whole, nullptr, [] { return false; });
  EXPECT_EQ(accepted.preparation.decided, "parts+wrap");
  EXPECT_EQ(accepted.parts_left_out(), 0u);

  options.envelope.max_voxels = 64;  // under the dome's own grid
  PolygonMesh again = input();
  const PreparedMesh refused = prepare_input(again, nullptr, options);
  EXPECT_FALSE(refused.pending.any());
  EXPECT_EQ(refused.parts_left_out(), 1u);
}

// The worker's envelope asks its stop check (the job's time limit and cancel).
TEST(PrepareAuto, ADeferredEnvelopeStops) {
  PrepareOptions options = automatic();
  options.defer_envelopes = true;
  PolygonMesh input = testing::dome(2);
  PreparedMesh prepared = prepare_input(input, nullptr, options);
  ASSERT_TRUE(prepared.pending.any());
  try {
    build_envelopes(prepared, input, nullptr, [] { return true; });
    ADD_FAILURE() << "the envelope did not stop";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped");
  }
}

}  // namespace
}  // namespace spheremap
