// The remesh of an envelope carries the original's shading as a tangent-space normal map
// (normal_bake.h): decoded in the frame a glTF viewer builds from the remesh's NORMAL and
// TANGENT, each texel's normal is the original's at the closest point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/io/image_reader.h"
#include "core/map/pipeline.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/normal_bake.h"
#include "core/outputs/original_surface.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

PrepareOptions wrap_options() {
  PrepareOptions o;
  o.method = PrepareMethod::kWrap;
  o.envelope.resolution = 96;
  o.envelope.target_faces = 3000;
  return o;
}

// The outward normal of the torus (2 + cos u, ...) (tests/mesh_generators: R 2, r 1) at
// the point of it nearest to q.
Vec3 torus_normal(const Vec3& q) {
  const double ring = std::hypot(q.x, q.y);
  const Vec3 centre = ring > 0 ? Vec3{2 * q.x / ring, 2 * q.y / ring, 0} : Vec3{2, 0, 0};
  const Vec3 d = q - centre;
  return d * (1 / norm(d));
}

double degrees_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(dot(a, b) / (norm(a) * norm(b)), -1.0, 1.0)) * 180 / M_PI;
}

struct NormalCheck {
  size_t checked = 0, within = 0;
  size_t geometry_differs = 0;  // the remesh's own normal over 20 degrees from the wanted
};

// Per remesh vertex: the normal-map texel at its TEXCOORD_0, decoded with its NORMAL and
// TANGENT as glTF says (bitangent = cross(normal, tangent) * w, +Y up), against
// `want(closest point of the original)`.
template <typename Want>
NormalCheck check_normals(const BuiltRemesh& built, const PolygonMesh& original,
                          const std::vector<Triangle>& triangles, double degrees, Want want) {
  NormalCheck out;
  const GlbMesh& glb = built.glb;
  const std::optional<RgbaImage> image = decode_image(glb.normal_png, 1 << 24);
  if (!image || glb.tangents.size() != glb.positions.size()) return out;
  const TriangleTree tree(original.positions, triangles);
  for (size_t i = 0; i < glb.positions.size(); ++i) {
    const Vec3 wanted = want(tree.closest(glb.positions[i]).point);
    const auto& t = glb.texcoords[i];
    const int x = std::clamp(static_cast<int>(t[0] * image->width), 0, image->width - 1);
    const int y = std::clamp(static_cast<int>(t[1] * image->height), 0, image->height - 1);
    const uint8_t* px = &image->rgba[(static_cast<size_t>(y) * image->width + x) * 4];
    const Vec3 n = glb.normals[i];
    const Vec3 tangent{glb.tangents[i][0], glb.tangents[i][1], glb.tangents[i][2]};
    const Vec3 bitangent = cross(n, tangent) * glb.tangents[i][3];
    const auto unorm = [&](int k) { return px[k] / 255.0 * 2 - 1; };
    const Vec3 got = tangent * unorm(0) + bitangent * unorm(1) + n * unorm(2);
    ++out.checked;
    out.within += degrees_between(got, wanted) <= degrees;
    out.geometry_differs += degrees_between(n, wanted) > 20;
  }
  return out;
}

TEST(WrappedNormals, TangentsAreUnitOrthogonalAndRightHanded) {
  PolygonMesh input = testing::torus(24, 48);
  GltfAppearance none;
  const MappedMesh mapped = map_prepared(prepare_input(input, &none, wrap_options()), {});
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const BuiltRemesh built = build_remesh(mapped, 32, 0, nullptr, nullptr, nullptr, &*surface);
  ASSERT_EQ(built.glb.tangents.size(), built.glb.positions.size());
  for (size_t i = 0; i < built.glb.tangents.size(); ++i) {
    const auto& t = built.glb.tangents[i];
    const Vec3 tangent{t[0], t[1], t[2]};
    EXPECT_NEAR(norm(tangent), 1, 1e-6);
    EXPECT_NEAR(dot(tangent, built.glb.normals[i]), 0, 1e-6);
    // The square's v grows upward in the texture and the grid is counter-clockwise seen
    // from outside: every frame right-handed.
    EXPECT_EQ(t[3], 1.0f);
  }
}

TEST(WrappedNormals, ComputedNormalsOfTheOriginalAreBakedInTheRemeshFrame) {
  // No look: the original's own area-weighted vertex normals (a fine torus's are within a
  // degree or two of the analytic ones).
  PolygonMesh input = testing::torus(24, 48);
  const PolygonMesh original = input;
  GltfAppearance none;
  const MappedMesh mapped = map_prepared(prepare_input(input, &none, wrap_options()), {});
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const BuiltRemesh built = build_remesh(mapped, 64, 0, nullptr, nullptr, nullptr, &*surface);
  ASSERT_FALSE(built.glb.normal_png.empty());
  EXPECT_TRUE(built.glb.base_color_png.empty());  // no look: shading only
  const nlohmann::json& m = built.metrics["normal_map"];
  EXPECT_EQ(m["size"], 256);
  EXPECT_EQ(m["unlocated_texels"], 0);
  EXPECT_NE(m["normals"].get<std::string>().find("area-weighted"), std::string::npos);
  std::printf("normal map bake: %.3f s\n", built.metrics["seconds"]["normal_map"].get<double>());
  const NormalCheck check = check_normals(built, original, surface->triangles, 8,
                                          [](const Vec3& q) { return torus_normal(q); });
  std::printf("normals: checked %zu, within 8 degrees %zu, remesh normal off by > 20: %zu\n",
              check.checked, check.within, check.geometry_differs);
  EXPECT_GT(check.checked, 4000u);
  EXPECT_GE(check.within, check.checked * 95 / 100);
  // Where the envelope closed the hole its own normals are far from the original's: the
  // map is what gives those back.
  EXPECT_GT(check.geometry_differs, check.checked / 20);
}

TEST(WrappedNormals, TheOriginalsNormalAttributeIsBakedWhenItHasOne) {
  // NORMAL tilted toward +z everywhere: not the geometry's, so the bake must have read it.
  PolygonMesh input = testing::torus(24, 48);
  const PolygonMesh original = input;
  auto tilted = [](const Vec3& n) {
    const Vec3 t = n + Vec3{0, 0, 0.7};
    return t * (1 / norm(t));
  };
  GltfAppearance look;
  GltfAppearance::Primitive primitive;
  primitive.vertex_count = static_cast<uint32_t>(input.vertex_count());
  primitive.face_count = static_cast<uint32_t>(input.face_count());
  primitive.attributes = {"NORMAL"};
  primitive.world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  look.primitives = {primitive};
  GltfAppearance::Attribute normals{"NORMAL", 3, {}};
  for (const Vec3& p : input.positions) {
    const Vec3 n = tilted(torus_normal(p));
    for (double c : {n.x, n.y, n.z}) normals.values.push_back(static_cast<float>(c));
  }
  look.attributes = {normals};
  const MappedMesh mapped = map_prepared(prepare_input(input, &look, wrap_options()), {});
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const BuiltRemesh built = build_remesh(mapped, 64, 0, nullptr, nullptr, nullptr, &*surface);
  ASSERT_FALSE(built.glb.normal_png.empty());
  EXPECT_NE(built.metrics["normal_map"]["normals"].get<std::string>().find("NORMAL"),
            std::string::npos);
  const NormalCheck check = check_normals(built, original, surface->triangles, 8,
                                          [&](const Vec3& q) { return tilted(torus_normal(q)); });
  const NormalCheck untilted = check_normals(built, original, surface->triangles, 8,
                                             [](const Vec3& q) { return torus_normal(q); });
  std::printf("tilted normals: checked %zu, within 8 degrees %zu (untilted %zu)\n", check.checked,
              check.within, untilted.within);
  EXPECT_GE(check.within, check.checked * 95 / 100);
  EXPECT_LT(untilted.within, check.checked / 2);
}

TEST(WrappedNormals, TheNormalAttributeTurnsWithItsNodesTransform) {
  // One triangle whose primitive's node scales z by 4 and turns 90 degrees about x: a
  // NORMAL turns by the inverse transpose (scaled by 1/4 in z before the turn).
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const uint32_t corners[3] = {0, 1, 2};
  mesh.add_face(corners);
  GltfAppearance look;
  GltfAppearance::Primitive primitive;
  primitive.vertex_count = 3;
  primitive.face_count = 1;
  primitive.attributes = {"NORMAL"};
  // Column-major: scale z by 4, then turn (x, y, z) -> (x, -z, y).
  primitive.world = {1, 0, 0, 0, 0, 0, 1, 0, 0, -4, 0, 0, 0, 0, 0, 1};
  look.primitives = {primitive};
  const float s = static_cast<float>(1 / std::sqrt(2.0));
  look.attributes = {{"NORMAL", 3, {0, s, s, 0, s, s, 0, s, s}}};
  const OriginalSurface original = original_surface(mesh, &look);
  const ShadingNormals normals(original);
  EXPECT_TRUE(normals.from_attribute());
  const Vec3 n = normals.at(0, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  // Local (0, 1, 1) -> scaled (0, 1, 1/4) -> turned (0, -1/4, 1), normalized.
  const Vec3 want = Vec3{0, -0.25, 1} * (1 / std::sqrt(1 + 0.0625));
  EXPECT_NEAR(n.x, want.x, 1e-6);
  EXPECT_NEAR(n.y, want.y, 1e-6);
  EXPECT_NEAR(n.z, want.z, 1e-6);
  // Without the attribute: the face's own normal.
  const OriginalSurface bare = original_surface(mesh, nullptr);
  const ShadingNormals computed(bare);
  EXPECT_FALSE(computed.from_attribute());
  const Vec3 face = computed.at(0, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  EXPECT_NEAR(face.z, 1, 1e-12);
}

// A wrapped part's shading normals come from its own faces' primitives: a part drawn by a
// primitive without NORMAL gets computed normals even where another primitive of the asset
// has the attribute, and another part's faces at the same positions do not bend them.
TEST(WrappedNormals, APartsNormalsComeFromItsOwnFacesAndPrimitive) {
  PolygonMesh mesh;
  // Primitive 0: a triangle tilted out of z = 0, NORMAL given (+x). Primitive 1: a flat
  // triangle in z = 0 on the same three positions (corners of its own).
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const uint32_t tilted[3] = {0, 1, 2}, flat[3] = {3, 4, 5};
  mesh.add_face(tilted);
  mesh.add_face(flat);
  GltfAppearance look;
  GltfAppearance::Primitive with, without;
  with.vertex_count = 3, with.face_count = 1, with.attributes = {"NORMAL"};
  with.world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  without = with;
  without.first_vertex = 3, without.first_face = 1, without.attributes = {};
  look.primitives = {with, without};
  look.attributes = {{"NORMAL", 3, {1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}}};
  const std::vector<uint32_t> second = {1};
  const OriginalSurface part = original_surface(mesh, &look, &second);
  const ShadingNormals normals(part);
  EXPECT_FALSE(normals.from_attribute());
  const Vec3 n = normals.at(0, {0.2, 0.3, 0.5});
  EXPECT_NEAR(n.z, 1, 1e-12);  // its own face's normal, not bent by the tilted face
  const std::vector<uint32_t> first = {0};
  const OriginalSurface other = original_surface(mesh, &look, &first);
  const ShadingNormals given(other);
  EXPECT_TRUE(given.from_attribute());
  EXPECT_NEAR(given.at(0, {0.2, 0.3, 0.5}).x, 1, 1e-12);
}

TEST(WrappedNormals, AMeshMappedAsItIsGetsNoNormalMap) {
  PolygonMesh input = testing::icosphere(3);
  GltfAppearance none;
  PrepareOptions o = wrap_options();
  o.method = PrepareMethod::kAuto;
  const MappedMesh mapped = map_prepared(prepare_input(input, &none, o), {});
  const BuiltRemesh built = build_remesh(mapped, 32, 0, nullptr, nullptr);
  EXPECT_TRUE(built.glb.normal_png.empty());
  EXPECT_TRUE(built.glb.tangents.empty());
  EXPECT_FALSE(built.metrics.contains("normal_map"));
}

}  // namespace
}  // namespace spheremap
