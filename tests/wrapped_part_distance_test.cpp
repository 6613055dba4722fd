// prepare=auto wraps a part that does not map even once repaired; the repair's hole fills
// stay in the part the envelope is made of, so the envelope covers the hole where the fill
// was. Its distances (metrics parts[k].wrapped) are those to the part's own input faces,
// which every output measures and bakes against: a fill inside the envelope must not hide
// how far the envelope is from the input there.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/mesh/surface_distance.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// testing::icosphere(3) (radius 1) without its faces above z = 0.93 (a round hole about
// 0.7 across, 3.5% of the area, which the repair fills) and below z = -0.6 (a hole of a
// fifth of the area, too large to fill): with double_open_sheets off, a part that does not
// map even once repaired, so it is wrapped. (It had a fin for that; a fin now lets go of
// the sphere, sheet_ends.h, and the part maps.)
PolygonMesh sphere_with_two_holes() {
  const PolygonMesh sphere = testing::icosphere(3);
  PolygonMesh out;
  out.positions = sphere.positions;
  for (size_t f = 0; f < sphere.face_count(); ++f) {
    double z = 0;
    for (uint32_t v : sphere.face(f)) z += sphere.positions[v].z / 3;
    if (z <= 0.93 && z >= -0.6) out.add_face(sphere.face(f));
  }
  return out;
}

// The diagonal of the bounding box of the mesh's face corners (the asset's, as prepare
// measures it: vertices referenced by no face, as in the hole, do not count).
double diagonal(const PolygonMesh& mesh) {
  Vec3 lo = mesh.positions[mesh.face(0)[0]], hi = lo;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) {
      const Vec3& p = mesh.positions[v];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  return norm(hi - lo);
}

std::vector<Triangle> triangles_of(const PolygonMesh& mesh, const std::vector<uint32_t>& faces) {
  std::vector<Triangle> out;
  for (uint32_t f : faces) {
    const auto c = mesh.face(f);
    for (size_t k = 2; k < c.size(); ++k) out.push_back({c[0], c[k - 1], c[k]});
  }
  return out;
}

TEST(WrappedPartDistance, IsMeasuredToThePartsInputFacesNotItsFills) {
  // A sphere (maps) and the sphere with two holes (its small hole filled; wrapped).
  PolygonMesh input = testing::assembled(
      {{testing::icosphere(2), {0, 0, 0}}, {sphere_with_two_holes(), {6, 0, 0}}});
  PrepareOptions options;
  options.method = PrepareMethod::kAuto;
  options.double_open_sheets = false;
  options.envelope.resolution = 96;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  ASSERT_EQ(prepared.preparation.decided, "parts+wrap");
  ASSERT_EQ(prepared.preparation.holes_filled, 1u);
  const auto wrapped = std::find_if(prepared.parts.begin(), prepared.parts.end(),
                                    [](const PartReport& p) { return p.wrapped; });
  ASSERT_NE(wrapped, prepared.parts.end());
  const EnvelopeReport& report = wrapped->envelope;

  // The envelope as it replaced the part, and the distance to the holed sphere's input faces.
  const std::vector<MeshPart> parts = connected_parts(prepared.welded.mesh);
  const auto envelope = std::find_if(parts.begin(), parts.end(), [&](const MeshPart& p) {
    return p.mesh.face_count() == report.faces;
  });
  ASSERT_NE(envelope, parts.end());
  std::vector<uint32_t> all(envelope->mesh.face_count());
  for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
  const SurfaceDistance d =
      surface_distance(input.positions, triangles_of(input, wrapped->original_faces),
                       envelope->mesh.positions, triangles_of(envelope->mesh, all), 1);
  const double scale = d.diagonal / diagonal(input);
  EXPECT_NEAR(report.envelope_to_original, d.max_b_to_a * scale, 1e-12);
  EXPECT_NEAR(report.original_to_envelope, d.max_a_to_b * scale, 1e-12);
  EXPECT_NEAR(report.hausdorff, d.hausdorff * scale, 1e-12);
  // Over the hole the envelope follows the fill, about 0.26 from the input's faces on an
  // asset 8.5 across: 3.1% of the diagonal (measured against the part with its fill: 1.0%).
  EXPECT_GT(report.envelope_to_original, 0.02);
}

}  // namespace
}  // namespace spheremap
