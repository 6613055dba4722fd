// Outputs of an envelope (prepare wrap, or auto wrapping the whole or a part) keep the
// original beside them: the remesh measures its distance to the ORIGINAL triangles and
// bakes the original's base colour by closest point (original_surface.h,
// base_color_bake.h). A mesh that maps as it is gets none of it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "core/io/gltf_reader.h"
#include "core/io/image_reader.h"
#include "core/map/pipeline.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/asset_builders.h"
#include "core/outputs/original_surface.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

struct Textured {
  PolygonMesh mesh;
  GltfAppearance look;
};

// `mesh` as a textured GLB read back (testing::textured_glb: TEXCOORD_0 is the planar
// projection (x, y) over the larger of the x and y extents).
Textured textured(const PolygonMesh& mesh) {
  const std::string file = testing::textured_glb(mesh);
  Textured out;
  out.mesh = read_gltf({reinterpret_cast<const uint8_t*>(file.data()), file.size()}, {}, nullptr,
                       nullptr, &out.look);
  return out;
}

PrepareOptions options(PrepareMethod method) {
  PrepareOptions o;
  o.method = method;
  o.envelope.resolution = 96;  // voxel: 1/96 of the diagonal
  o.envelope.target_faces = 3000;
  o.double_open_sheets = false;  // the open domes here stand for parts only an envelope maps
  return o;
}

struct ColourCheck {
  size_t checked = 0, matched = 0;
  std::set<std::array<int, 3>> colours;  // of the matches
};

// Every remesh vertex of `built` whose closest point on `original` (triangles of
// `original_mesh`) lies well inside one of the texture's squares: the baked texel at the
// vertex's TEXCOORD_0 against that square's colour.
ColourCheck check_colours(const BuiltRemesh& built, const PolygonMesh& original_mesh,
                          const std::vector<Triangle>& original) {
  ColourCheck out;
  const std::optional<RgbaImage> image = decode_image(built.glb.base_color_png, 1 << 24);
  if (!image) return out;
  Vec3 lo = original_mesh.positions[0], hi = lo;
  for (const Vec3& p : original_mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  const TriangleTree tree(original_mesh.positions, original);
  for (size_t i = 0; i < built.glb.positions.size(); ++i) {
    const Vec3 q = tree.closest(built.glb.positions[i]).point;
    const double u = (q.x - lo.x) / extent, v = (q.y - lo.y) / extent;
    // A texel (1/16) or more from every square's border: no blend of two squares.
    auto inside = [](double x) {
      const double in_square = x * 4 - std::floor(x * 4);
      return in_square > 0.25 && in_square < 0.75 && x > 0 && x < 1;
    };
    if (!inside(u) || !inside(v)) continue;
    const auto& t = built.glb.texcoords[i];
    const int x = std::clamp(static_cast<int>(t[0] * image->width), 0, image->width - 1);
    const int y = std::clamp(static_cast<int>(t[1] * image->height), 0, image->height - 1);
    const uint8_t* px = &image->rgba[(static_cast<size_t>(y) * image->width + x) * 4];
    const std::array<int, 3> want = testing::textured_glb_color(u, v);
    ++out.checked;
    bool same = true;
    for (int k = 0; k < 3; ++k) same = same && std::abs(px[k] - want[k]) <= 8;
    if (same) {
      ++out.matched;
      out.colours.insert(want);
    }
  }
  return out;
}

TEST(WrappedLook, AWrappedTorusKeepsItsOriginalAndLook) {
  Textured in = textured(testing::torus(32, 16));
  const PolygonMesh original = in.mesh;
  const PreparedMesh prepared = prepare_input(in.mesh, &in.look, options(PrepareMethod::kWrap));
  EXPECT_TRUE(in.look.empty());  // the envelope has no look of its own
  ASSERT_TRUE(prepared.original);
  EXPECT_EQ(prepared.original->mesh.positions, original.positions);
  EXPECT_EQ(prepared.original->mesh.face_count(), original.face_count());
  ASSERT_EQ(prepared.original->look.primitives.size(), 1u);
  EXPECT_EQ(prepared.original->look.image_data.size(), 1u);
}

TEST(WrappedLook, AWrappedTorusRemeshIsMeasuredAndColouredFromTheOriginal) {
  Textured in = textured(testing::torus(32, 16));
  const PolygonMesh original = in.mesh;
  const MappedMesh mapped =
      map_prepared(prepare_input(in.mesh, &in.look, options(PrepareMethod::kWrap)), {});
  const EnvelopeReport& envelope = mapped.prepared.preparation.envelope;
  const RemeshAsset asset = remesh_asset(mapped, 64, 0, &in.mesh, &in.look);
  const nlohmann::json& m = asset.metrics;
  ASSERT_TRUE(m.contains("distance_to_original"));
  const double hausdorff = m["distance_to_original"]["hausdorff"].get<double>();
  const double rms = m["distance_to_original"]["rms"].get<double>();
  EXPECT_TRUE(std::isfinite(hausdorff));
  EXPECT_GT(rms, 0);
  std::printf(
      "remesh to original: hausdorff %.4f rms %.4f; envelope %.4f %.4f; remesh to "
      "envelope %.4f %.4f\n",
      hausdorff, rms, envelope.hausdorff, envelope.rms, m["distance"]["hausdorff"].get<double>(),
      m["distance"]["rms"].get<double>());
  // The largest distance is where the handle was cut or filled, as the envelope's own; the
  // RMS within a few voxels (1/96 of the diagonal) of the original.
  EXPECT_NEAR(hausdorff, envelope.hausdorff, 2.0 / 96);
  EXPECT_LT(rms, 4.0 / 96);
  // About the offset (1.5 voxels) from the original, closer to the envelope it samples.
  EXPECT_GT(rms, m["distance"]["rms"].get<double>());
  EXPECT_NE(hausdorff, m["distance"]["hausdorff"].get<double>());
  EXPECT_EQ(m["original_look"], "baked by closest point on the original");
  EXPECT_EQ(m["texture"]["images_decoded"], 1);
  EXPECT_EQ(m["texture"]["unlocated_texels"], 0);

  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  EXPECT_EQ(surface->triangles.size(), original.face_count());  // read back as triangles
  const BuiltRemesh built = build_remesh(mapped, 64, 0, nullptr, nullptr, nullptr, &*surface);
  const ColourCheck colours = check_colours(built, original, surface->triangles);
  std::printf("texels checked %zu, matched %zu\n", colours.checked, colours.matched);
  EXPECT_GT(colours.checked, 200u);
  EXPECT_GE(colours.matched, colours.checked * 9 / 10);
  EXPECT_EQ(colours.colours.size(), 4u);  // red, green, blue and white squares all found
}

TEST(WrappedLook, AWrappedMeshWithoutALookBakesNothingAndSaysSo) {
  PolygonMesh input = testing::torus(32, 16);
  GltfAppearance none;
  const MappedMesh mapped =
      map_prepared(prepare_input(input, &none, options(PrepareMethod::kWrap)), {});
  const RemeshAsset asset = remesh_asset(mapped, 32, 0, &input, &none);
  EXPECT_TRUE(asset.metrics.contains("distance_to_original"));
  EXPECT_FALSE(asset.metrics.contains("texture"));
  EXPECT_EQ(asset.metrics["original_look"].get<std::string>().rfind("none", 0), 0u);
}

TEST(WrappedLook, AMaterialWithoutImageIsBakedAsItsFactor) {
  PolygonMesh input = testing::torus(32, 16);
  GltfAppearance look;
  GltfAppearance::Primitive primitive;
  primitive.material = 0;
  primitive.vertex_count = static_cast<uint32_t>(input.vertex_count());
  primitive.face_count = static_cast<uint32_t>(input.face_count());
  look.primitives = {primitive};
  look.materials = nlohmann::json::array(
      {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 1.0, 0.0, 1.0}}}}}});
  const MappedMesh mapped =
      map_prepared(prepare_input(input, &look, options(PrepareMethod::kWrap)), {});
  const RemeshAsset asset = remesh_asset(mapped, 32, 0, &input, &look);
  EXPECT_EQ(asset.metrics["original_look"].get<std::string>().rfind("material factors", 0), 0u);
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const BuiltRemesh built = build_remesh(mapped, 32, 0, nullptr, nullptr, nullptr, &*surface);
  const std::optional<RgbaImage> image = decode_image(built.glb.base_color_png, 1 << 24);
  ASSERT_TRUE(image);
  size_t green = 0;
  for (size_t k = 0; k < image->rgba.size(); k += 4)
    green += image->rgba[k] == 0 && image->rgba[k + 1] == 255 && image->rgba[k + 2] == 0;
  EXPECT_EQ(green, image->rgba.size() / 4);  // every texel the factor
}

TEST(WrappedLook, AutoWrapsAnOpenPartAndColoursItsRemeshFromThatPart) {
  // A sphere (maps as it is) and an open dome (its hole too large to fill: wrapped).
  const PolygonMesh sphere = testing::icosphere(2), dome = testing::dome(3);
  Textured in = textured(testing::assembled({{sphere, {0, 0, 0}}, {dome, {3, 0, 0}}}));
  const PreparedMesh prepared = prepare_input(in.mesh, &in.look, options(PrepareMethod::kAuto));
  ASSERT_EQ(prepared.preparation.decided, "parts+wrap");
  EXPECT_FALSE(prepared.original);  // the input itself is the original
  EXPECT_FALSE(in.look.empty());
  size_t wrapped = 0;
  const PartReport* dome_report = nullptr;
  for (const PartReport& part : prepared.parts)
    if (part.wrapped) ++wrapped, dome_report = &part;
  ASSERT_EQ(wrapped, 1u);
  // The dome's faces, and only those (the sphere's come first).
  EXPECT_EQ(dome_report->original_faces.size(), dome.face_count());
  EXPECT_EQ(dome_report->original_faces.front(), sphere.face_count());
  const std::vector<uint32_t> dome_faces = dome_report->original_faces;

  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 2u);
  const RemeshAsset asset = remesh_asset(mapped, 64, 0, &in.mesh, &in.look);
  const nlohmann::json& m = asset.metrics;
  ASSERT_TRUE(m.contains("distance_to_original"));
  EXPECT_EQ(m["distance_to_original"]["wrapped_parts"], 1);
  size_t with_distance = 0;
  for (const nlohmann::json& part : m["parts"]) {
    if (!part.contains("distance_to_original")) {
      EXPECT_FALSE(part.contains("original_look"));  // mapped as it is: its distance is it
      continue;
    }
    ++with_distance;
    EXPECT_LT(part["distance_to_original"]["hausdorff"].get<double>(), 0.1);
    EXPECT_GT(part["distance_to_original"]["rms"].get<double>(),
              part["distance"]["rms"].get<double>());
    EXPECT_EQ(part["original_look"], "baked by closest point on the original");
  }
  EXPECT_EQ(with_distance, 1u);
  // In model units over the whole asset's diagonal: no more than over a part's.
  EXPECT_GT(m["distance_to_original"]["asset_hausdorff"].get<double>(), 0);
  EXPECT_LE(m["distance_to_original"]["asset_hausdorff"].get<double>(),
            m["distance_to_original"]["hausdorff"].get<double>());
  // The asset's distance to the original: at least its wrapped part's.
  EXPECT_GE(m["distance_to_original"]["hausdorff"].get<double>(),
            m["distance"]["hausdorff"].get<double>());

  // The wrapped part's remesh takes the dome's colours (the dome's texture coordinates are
  // those of the whole asset's projection).
  // Mapped parts pair with the reports of the parts that map, in order (map_parts.h).
  size_t dome_part = 0;
  for (size_t k = 0, mapped_k = 0; k < prepared.parts.size(); ++k) {
    if (!prepared.parts[k].mappable()) continue;
    if (prepared.parts[k].wrapped) dome_part = mapped_k;
    ++mapped_k;
  }
  const OriginalSurface surface = original_surface(in.mesh, &in.look, &dome_faces);
  const BuiltRemesh built =
      build_remesh(mapped.parts[dome_part].mapped, 64, 0, nullptr, nullptr, nullptr, &surface);
  const ColourCheck colours = check_colours(built, in.mesh, surface.triangles);
  std::printf("texels checked %zu, matched %zu\n", colours.checked, colours.matched);
  EXPECT_GT(colours.checked, 50u);
  EXPECT_GE(colours.matched, colours.checked * 9 / 10);
  EXPECT_GE(colours.colours.size(), 2u);
}

// A look for `input`: its vertices red where x < 0 and blue elsewhere (COLOR_0, no material).
GltfAppearance two_colours(const PolygonMesh& input) {
  GltfAppearance look;
  GltfAppearance::Primitive primitive;
  primitive.vertex_count = static_cast<uint32_t>(input.vertex_count());
  primitive.face_count = static_cast<uint32_t>(input.face_count());
  primitive.attributes = {"COLOR_0"};
  look.primitives = {primitive};
  GltfAppearance::Attribute colours{"COLOR_0", 3, {}};
  for (const Vec3& p : input.positions)
    for (float c : p.x < 0 ? std::array<float, 3>{1, 0, 0} : std::array<float, 3>{0, 0, 1})
      colours.values.push_back(c);
  look.attributes = {colours};
  return look;
}

TEST(WrappedLook, VertexColoursAreBakedByClosestPoint) {
  PolygonMesh input = testing::torus(32, 16);
  const PolygonMesh original = input;
  GltfAppearance look = two_colours(input);
  const MappedMesh mapped =
      map_prepared(prepare_input(input, &look, options(PrepareMethod::kWrap)), {});
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const BuiltRemesh built = build_remesh(mapped, 64, 0, nullptr, nullptr, nullptr, &*surface);
  const std::optional<RgbaImage> image = decode_image(built.glb.base_color_png, 1 << 24);
  ASSERT_TRUE(image);
  const TriangleTree tree(original.positions, surface->triangles);
  size_t checked = 0, matched = 0, red = 0;
  for (size_t i = 0; i < built.glb.positions.size(); ++i) {
    const double x = tree.closest(built.glb.positions[i]).point.x;
    // Faces with a corner at x = 0 (v = 90 degrees) reach |x| = 3 sin 22.5 = 1.15: blended.
    if (std::abs(x) < 1.2) continue;
    const auto& t = built.glb.texcoords[i];
    const int column = std::clamp(static_cast<int>(t[0] * image->width), 0, image->width - 1);
    const int row = std::clamp(static_cast<int>(t[1] * image->height), 0, image->height - 1);
    const uint8_t* px = &image->rgba[(static_cast<size_t>(row) * image->width + column) * 4];
    const bool want_red = x < 0;
    ++checked;
    red += want_red;
    matched += want_red ? px[0] > 240 && px[2] < 15 : px[2] > 240 && px[0] < 15;
  }
  std::printf("vertex colours: checked %zu (red %zu), matched %zu\n", checked, red, matched);
  EXPECT_GT(red, 100u);
  EXPECT_GT(checked - red, 100u);
  EXPECT_GE(matched, checked * 95 / 100);
}

struct VertexColourCheck {
  size_t checked = 0, red = 0, matched = 0;
};

// Per vertex at `surface[v]` whose closest point of the original lies well away from x = 0:
// colours[v] red for x < 0, blue otherwise.
VertexColourCheck check_vertex_colours(std::span<const Vec3> surface,
                                       std::span<const std::array<float, 3>> colours,
                                       const TriangleTree& tree) {
  VertexColourCheck out;
  for (size_t v = 0; v < surface.size() && v < colours.size(); ++v) {
    const double x = tree.closest(surface[v]).point.x;
    if (std::abs(x) < 1.2) continue;  // faces with a corner at x = 0 blend the two
    ++out.checked;
    const bool want_red = x < 0;
    out.red += want_red;
    const auto& c = colours[v];
    out.matched += want_red ? c[0] > 0.99f && c[2] < 0.01f : c[2] > 0.99f && c[0] < 0.01f;
  }
  return out;
}

TEST(WrappedLook, TheWrappedSphereAndUvMeshCarryTheOriginalsColourPerVertex) {
  PolygonMesh input = testing::torus(32, 16);
  const PolygonMesh original = input;
  GltfAppearance look = two_colours(input);
  const MappedMesh mapped =
      map_prepared(prepare_input(input, &look, options(PrepareMethod::kWrap)), {});
  const std::optional<OriginalSurface> surface = wrapped_original(mapped);
  ASSERT_TRUE(surface);
  const TriangleTree tree(original.positions, surface->triangles);

  const BuiltAsset uv = build_uv(mapped, &*surface);
  ASSERT_EQ(uv.glb.colors.size(), uv.glb.positions.size());
  const VertexColourCheck on_uv = check_vertex_colours(uv.glb.positions, uv.glb.colors, tree);
  std::printf("uv COLOR_0: checked %zu (red %zu), matched %zu\n", on_uv.checked, on_uv.red,
              on_uv.matched);
  EXPECT_GT(on_uv.red, 100u);
  EXPECT_GT(on_uv.checked - on_uv.red, 100u);
  EXPECT_EQ(on_uv.matched, on_uv.checked);
  EXPECT_TRUE(uv_asset(mapped).metrics.contains("vertex_colors"));
  EXPECT_TRUE(morph_asset(mapped, 4).metrics.contains("vertex_colors"));

  // The sphere as written (the envelope's own vertices, in the input's layout), read back.
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0, &look);
  EXPECT_TRUE(sphere.metrics.contains("vertex_colors"));
  GltfAppearance written;
  const PolygonMesh read =
      read_gltf({reinterpret_cast<const uint8_t*>(sphere.glb.data()), sphere.glb.size()}, {},
                nullptr, nullptr, &written);
  const GltfAppearance::Attribute* colour = written.attribute("COLOR_0");
  ASSERT_TRUE(colour);
  ASSERT_EQ(read.vertex_count(), input.vertex_count());
  std::vector<std::array<float, 3>> per_vertex;
  for (size_t v = 0; v < read.vertex_count(); ++v)
    per_vertex.push_back({colour->values[v * colour->components],
                          colour->values[v * colour->components + 1],
                          colour->values[v * colour->components + 2]});
  const VertexColourCheck on_sphere = check_vertex_colours(input.positions, per_vertex, tree);
  std::printf("sphere COLOR_0: checked %zu (red %zu), matched %zu\n", on_sphere.checked,
              on_sphere.red, on_sphere.matched);
  EXPECT_GT(on_sphere.red, 50u);
  EXPECT_GT(on_sphere.checked - on_sphere.red, 50u);
  EXPECT_EQ(on_sphere.matched, on_sphere.checked);
}

TEST(WrappedLook, AMeshMappedAsItIsHasNoVertexColours) {
  Textured in = textured(testing::icosphere(3));
  const MappedMesh mapped =
      map_prepared(prepare_input(in.mesh, &in.look, options(PrepareMethod::kAuto)), {});
  EXPECT_TRUE(build_uv(mapped).glb.colors.empty());
  EXPECT_FALSE(uv_asset(mapped, &in.mesh, &in.look).metrics.contains("vertex_colors"));
}

TEST(WrappedLook, AnAutoWrappedPartsSphereAndUvMeshCarryItsColourPerVertex) {
  // A sphere (maps as it is) and an open dome (wrapped): only the dome's meshes coloured.
  const PolygonMesh sphere = testing::icosphere(2), dome = testing::dome(3);
  Textured in = textured(testing::assembled({{sphere, {0, 0, 0}}, {dome, {3, 0, 0}}}));
  const MappedMesh mapped =
      map_prepared(prepare_input(in.mesh, &in.look, options(PrepareMethod::kAuto)), {});
  ASSERT_EQ(mapped.parts.size(), 2u);
  const SphereAsset spheres =
      sphere_asset(in.mesh, mapped, {}, SphereLayout::kOriginal, 0, &in.look);
  EXPECT_TRUE(spheres.metrics.contains("vertex_colors"));
  GltfAppearance written;
  read_gltf({reinterpret_cast<const uint8_t*>(spheres.glb.data()), spheres.glb.size()}, {}, nullptr,
            nullptr, &written);
  ASSERT_EQ(written.primitives.size(), 2u);
  EXPECT_NE(written.primitives[0].has("COLOR_0"), written.primitives[1].has("COLOR_0"));
  const UvAsset uv = uv_asset(mapped, &in.mesh, &in.look);
  size_t coloured = 0;
  for (const nlohmann::json& part : uv.metrics["parts"]) coloured += part.contains("vertex_colors");
  EXPECT_EQ(coloured, 1u);
}

TEST(WrappedLook, PartsShareTheirDecodedImage) {
  // Two open domes, each wrapped alone, both textured from the one image: decoded once.
  const PolygonMesh dome = testing::dome(2);
  Textured in = textured(testing::assembled({{dome, {0, 0, 0}}, {dome, {3, 0, 0}}}));
  const PreparedMesh prepared = prepare_input(in.mesh, &in.look, options(PrepareMethod::kAuto));
  ASSERT_EQ(prepared.preparation.decided, "parts+wrap");
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 2u);
  const RemeshAsset asset = remesh_asset(mapped, 32, 0, &in.mesh, &in.look);
  size_t decoded = 0, textured_parts = 0;
  for (const nlohmann::json& part : asset.metrics["parts"]) {
    ASSERT_TRUE(part.contains("texture"));
    ++textured_parts;
    decoded += part["texture"]["images_decoded"].get<size_t>();
  }
  EXPECT_EQ(textured_parts, 2u);
  EXPECT_EQ(decoded, 1u);
}

TEST(WrappedLook, AClosedGenusZeroInputIsUntouched) {
  Textured in = textured(testing::icosphere(3));
  const PolygonMesh input = in.mesh;
  const PreparedMesh prepared = prepare_input(in.mesh, &in.look, options(PrepareMethod::kAuto));
  EXPECT_EQ(prepared.preparation.decided, "exact");
  EXPECT_FALSE(prepared.original);
  EXPECT_EQ(in.mesh.positions, input.positions);
  const MappedMesh mapped = map_prepared(prepared, {});
  const RemeshAsset asset = remesh_asset(mapped, 32, 0, &in.mesh, &in.look);
  EXPECT_FALSE(asset.metrics.contains("distance_to_original"));
  EXPECT_FALSE(asset.metrics.contains("original_look"));
  EXPECT_TRUE(asset.metrics.contains("texture"));  // baked through the map, as before
}

}  // namespace
}  // namespace spheremap
