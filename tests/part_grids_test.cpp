// The remesh grid of each part: samples per unit area alike while the parts' samples
// together fit kPartSampleBudget grids of the asked resolution, scaled down together past it;
// each part's baked texture scaled with its grid.
#include <gtest/gtest.h>

#include <vector>

#include "core/io/gltf_appearance.h"
#include "core/io/image_reader.h"
#include "core/map/map_parts.h"
#include "core/outputs/map_outputs.h"
#include "core/outputs/part_grids.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

double samples(const std::vector<int>& grids) {
  double total = 0;
  for (int grid : grids) total += (grid + 1.0) * (grid + 1.0);
  return total;
}

TEST(PartGrids, TheLargestPartGetsTheResolutionAndSmallerOnesTheirAreasRoot) {
  const std::vector<double> areas = {4.0, 1.0, 0.25, 1e-9};
  EXPECT_EQ(part_grids(128, areas), (std::vector<int>{128, 64, 32, 8}));
  EXPECT_EQ(part_grids(4, areas), (std::vector<int>{4, 4, 4, 4}));  // never above N
  EXPECT_EQ(part_grids(64, std::vector<double>{0.0, 0.0}), (std::vector<int>{64, 64}));
}

// A rod half as long as the largest part but of a ten-thousandth of its area: by area alone
// it would get the smallest grid; by its length it gets half the resolution.
TEST(PartGrids, ALongThinPartGetsAGridForItsLength) {
  const std::vector<double> areas = {1.0, 1e-4, 1e-4}, diagonals = {1.5, 0.75, 0.01};
  EXPECT_EQ(part_grids(128, areas), (std::vector<int>{128, 8, 8}));
  EXPECT_EQ(part_grids(128, areas, diagonals), (std::vector<int>{128, 64, 8}));
  // The longest part need not be the largest: both get the whole resolution.
  EXPECT_EQ(part_grids(64, std::vector<double>{1.0, 0.01}, std::vector<double>{1.0, 2.0}),
            (std::vector<int>{64, 64}));
}

TEST(PartGrids, ManyEqualPartsShareTheBudgetAlike) {
  const std::vector<double> areas(500, 1.0);
  const std::vector<int> grids = part_grids(256, areas);
  const double budget = kPartSampleBudget * 257.0 * 257.0;
  EXPECT_LE(samples(grids), budget);
  EXPECT_GT(samples(grids), 0.7 * budget);  // the budget is used, not wasted
  for (int grid : grids) {
    EXPECT_EQ(grid, grids[0]);
    EXPECT_EQ(grid % 2, 0);
  }
  EXPECT_LT(grids[0], 256);
}

// One large part among a cloud of fragments: it keeps the largest grid, every grid shrinks
// by the same factor, and fragments go down to the octahedron (N = 2), no further.
TEST(PartGrids, FragmentsShrinkToTheOctahedronAndTheLargestStaysLargest) {
  std::vector<double> areas(20000, 1e-4);
  areas.insert(areas.begin(), 1.0);
  const std::vector<int> grids = part_grids(256, areas);
  EXPECT_LE(samples(grids), kPartSampleBudget * 257.0 * 257.0);
  EXPECT_EQ(*std::max_element(grids.begin(), grids.end()), grids[0]);
  EXPECT_GE(grids[0], 200);
  for (size_t k = 1; k < grids.size(); ++k) EXPECT_EQ(grids[k], 2);
  // So many parts that even their octahedra pass the budget: each stays an octahedron.
  const std::vector<int> many = part_grids(16, std::vector<double>(5000, 1.0));
  for (int grid : many) EXPECT_EQ(grid, 2);
}

// End to end: 300 equal closed parts remeshed at 64 hold about the budget's samples, where
// a full grid each would be 300 times one.
TEST(PartGrids, ARemeshOfManyEqualPartsHoldsTheBudget) {
  std::vector<std::pair<PolygonMesh, Vec3>> pieces;
  for (int k = 0; k < 300; ++k)
    pieces.push_back({testing::icosphere(1), {3.0 * (k % 20), 3.0 * (k / 20), 0}});
  PolygonMesh input = testing::assembled(pieces);
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_EQ(mapped.parts.size(), 300u);
  const RemeshAsset remesh = remesh_asset(mapped, 64);
  EXPECT_TRUE(remesh.metrics["closed_genus0"]);
  EXPECT_LE(remesh.metrics["samples"].get<double>(), kPartSampleBudget * 65 * 65);
  EXPECT_EQ(remesh.metrics["parts"].size(), 300u);
}

TEST(PartGrids, APartsTextureFollowsItsGrid) {
  EXPECT_EQ(remesh_texture_size(128), 256);
  EXPECT_EQ(remesh_texture_size(16), 256);
  EXPECT_EQ(remesh_texture_size(4096), 2048);
  EXPECT_EQ(part_texture_size(128, 128), 256);
  EXPECT_EQ(part_texture_size(128, 64), 128);
  EXPECT_EQ(part_texture_size(128, 2), kMinPartTexture);
  EXPECT_EQ(part_texture_size(1024, 512), 1024);
  EXPECT_EQ(part_texture_size(16, 8), 128);
}

// The PNG of mesh `mesh`'s base-colour texture in a remesh GLB.
RgbaImage part_texture(const testing::Glb& glb, size_t mesh) {
  const auto& json = glb.json;
  const size_t material = json["meshes"][mesh]["primitives"][0]["material"];
  const size_t texture =
      json["materials"][material]["pbrMetallicRoughness"]["baseColorTexture"]["index"];
  const size_t image = json["textures"][texture]["source"];
  const auto& view = json["bufferViews"][json["images"][image]["bufferView"].get<size_t>()];
  const auto png = decode_image(
      glb.bin.substr(view["byteOffset"].get<size_t>(), view["byteLength"].get<size_t>()), 1 << 22);
  return png ? *png : RgbaImage{};
}

// A large sphere and 80 small ones, each its own primitive and colour: each part's texture
// is as large as its grid says (the small ones far under the whole mesh's 256), and holds
// its own primitive's colour, found from the part's own faces.
TEST(PartGrids, EachPartBakesItsOwnColourAtItsOwnSize) {
  std::vector<std::pair<PolygonMesh, Vec3>> pieces;
  PolygonMesh large = testing::icosphere(3);
  for (Vec3& p : large.positions) p = p * 6.0;
  pieces.push_back({large, {0, 0, -20}});
  for (int k = 0; k < 80; ++k)
    pieces.push_back({testing::icosphere(1), {3.0 * (k % 10), 3.0 * (k / 10), 0}});
  PolygonMesh input = testing::assembled(pieces);
  // Piece k's colour: bits of k % 7 + 1 (linear 0 or 1 bakes to sRGB 0 or 255).
  auto colour = [](size_t k) {
    const int bits = static_cast<int>(k % 7) + 1;
    return std::array<int, 3>{bits & 1 ? 255 : 0, bits & 2 ? 255 : 0, bits & 4 ? 255 : 0};
  };
  GltfAppearance look;
  uint32_t first_face = 0, first_vertex = 0;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const std::array<int, 3> c = colour(k);
    look.materials.push_back(
        {{"pbrMetallicRoughness",
          {{"baseColorFactor", {c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, 1.0}}}}});
    GltfAppearance::Primitive p;
    p.material = static_cast<int64_t>(k);
    p.first_vertex = first_vertex, p.vertex_count = pieces[k].first.vertex_count();
    p.first_face = first_face, p.face_count = pieces[k].first.face_count();
    first_vertex += p.vertex_count, first_face += p.face_count;
    look.primitives.push_back(p);
  }
  const MappedMesh mapped = map_prepared(prepare_input(input, &look, {}), {});
  ASSERT_EQ(mapped.parts.size(), pieces.size());
  const RemeshAsset remesh = remesh_asset(mapped, 64, 1, &input, &look);
  const testing::Glb glb(remesh.glb);
  ASSERT_EQ(glb.json["meshes"].size(), pieces.size());
  size_t texels = 0;
  for (size_t m = 0; m < pieces.size(); ++m) {
    SCOPED_TRACE(m);
    const nlohmann::json& part = remesh.metrics["parts"][m];
    const int size = part["texture"]["size"];
    EXPECT_EQ(size, part_texture_size(64, part["resolution"]));
    const RgbaImage image = part_texture(glb, m);
    ASSERT_EQ(image.width, size);
    texels += static_cast<size_t>(size) * size;
    // Which piece: the one whose centre the mesh's bounding box is about.
    const auto& accessor =
        glb.json["accessors"]
                [glb.json["meshes"][m]["primitives"][0]["attributes"]["POSITION"].get<size_t>()];
    auto middle = [&](int i) {
      return (accessor["min"][i].get<double>() + accessor["max"][i].get<double>()) / 2;
    };
    const Vec3 centre{middle(0), middle(1), middle(2)};
    size_t piece = 0;
    for (size_t k = 1; k < pieces.size(); ++k)
      if (norm(pieces[k].second - centre) < norm(pieces[piece].second - centre)) piece = k;
    ASSERT_LT(norm(pieces[piece].second - centre), 0.5);
    const std::array<int, 3> want = colour(piece);
    size_t right = 0;
    for (size_t i = 0; i < image.rgba.size(); i += 4)
      right +=
          image.rgba[i] == want[0] && image.rgba[i + 1] == want[1] && image.rgba[i + 2] == want[2];
    EXPECT_EQ(right, image.rgba.size() / 4);
  }
  EXPECT_EQ(remesh.metrics["parts"][0]["texture"]["size"], 256);  // the large sphere
  EXPECT_LT(remesh.metrics["parts"][1]["texture"]["size"], 64);   // a small one
  // Within the samples' budget in whole textures; 81 textures of 256 were 5.3M texels.
  EXPECT_LE(texels, kPartSampleBudget * 256 * 256);
  EXPECT_LT(texels, 300000u);
}

}  // namespace
}  // namespace spheremap
