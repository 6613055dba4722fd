// The glTF reader against inputs that multiply its work by references (security findings
// "Security III"): images and buffers that all name one source are held and written once
// and capped in total; attribute accessors are checked (count, type) before they are
// decoded and decoded once; a read and a weld stop when asked (the intake deadline).
#include <gtest/gtest.h>

#include <set>

#include "core/io/gltf_reader.h"
#include "core/map/pipeline.h"
#include "core/outputs/base_color_bake.h"
#include "core/outputs/sphere_asset.h"
#include "tests/gltf_files.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

using testing::as_bytes;
using testing::Glb;
using testing::many_images_naming_one_view;
using testing::primitives_naming_one_big_accessor;

TEST(GltfLimits, ImagesNamingOneBufferViewAreHeldAndWrittenOnce) {
  const std::string file = many_images_naming_one_view(256 << 10, 480);
  GltfAppearance look;
  const PolygonMesh mesh = read_gltf(as_bytes(file), {}, nullptr, nullptr, &look);
  ASSERT_EQ(look.images.size(), 481u);
  EXPECT_EQ(look.image_data.size(), 2u);  // the texture's PNG and the shared one
  for (size_t i = 2; i < look.images.size(); ++i)
    EXPECT_EQ(look.image_source[i], look.image_source[1]);
  ASSERT_NE(look.image_bytes(480), nullptr);
  EXPECT_EQ(look.image_bytes(480)->size(), size_t{256 << 10});

  const MappedMesh mapped = map_mesh(mesh, {}, {});
  const std::string out = sphere_asset(mesh, mapped, {}, SphereLayout::kOriginal, 0, &look).glb;
  EXPECT_LT(out.size(), file.size() + (64u << 10));  // once, not 480 x 256 KB
  const Glb written(out);
  std::set<size_t> views;
  for (const auto& image : written.json["images"]) views.insert(image["bufferView"].get<size_t>());
  EXPECT_EQ(written.json["images"].size(), 481u);
  EXPECT_EQ(views.size(), 2u);
}

TEST(GltfLimits, ImageBytesOverTheResourceCapAreRefused) {
  const std::string file = many_images_naming_one_view(256 << 10, 1);
  GltfReadOptions options;
  options.max_resource_bytes = 128 << 10;
  GltfAppearance look;
  try {
    read_gltf(as_bytes(file), options, nullptr, nullptr, &look);
    FAIL() << "expected too_large";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "too_large");
    EXPECT_NE(std::string(e.what()).find("131072"), std::string::npos) << e.what();
  }
  options.max_resource_bytes = 512 << 10;  // room for it once
  EXPECT_NO_THROW(read_gltf(as_bytes(file), options, nullptr, nullptr, &look));
}

// Files by name, counting how often each is asked for.
class CountingResources : public GltfResources {
 public:
  explicit CountingResources(std::string bin) : bin_(std::move(bin)) {}
  std::optional<std::string> fetch(const std::string& path, size_t max_bytes) const override {
    ++fetches;
    if (path != "scene.bin") return std::nullopt;
    if (bin_.size() > max_bytes) throw InputError("too_large", "over max_bytes");
    return bin_;
  }
  std::string how_to_supply() const override { return "in the test"; }
  mutable size_t fetches = 0;

 private:
  std::string bin_;
};

TEST(GltfLimits, BuffersNamingOneFileFetchItOnce) {
  Glb glb(testing::sphere_glb());
  const size_t length = glb.bin.size();
  glb.json["buffers"] = nlohmann::json::array();
  for (int i = 0; i < 100; ++i)
    glb.json["buffers"].push_back({{"uri", "scene.bin"}, {"byteLength", length}});
  glb.json["bufferViews"][0]["buffer"] = 99;  // one view reads the last of them
  const std::string gltf = glb.json.dump();
  const CountingResources files(glb.bin);
  GltfReadOptions options;
  options.max_resource_bytes = 2 * length;  // 100 copies would be 100 x length
  const PolygonMesh mesh = read_gltf(as_bytes(gltf), options, nullptr, &files);
  EXPECT_EQ(mesh.face_count(), testing::icosphere(1).face_count());
  EXPECT_EQ(files.fetches, 1u);

  options.max_resource_bytes = length / 2;
  try {
    read_gltf(as_bytes(gltf), options, nullptr, &files);
    FAIL() << "expected too_large";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "too_large") << e.what();
  }
}

// An accessor that is not a JSON object is named as its referrers name it, not by the
// JSON path ("accessors[0]").
TEST(GltfLimits, AnEntryThatIsNotAnObjectIsNamed) {
  const std::string file = R"({"asset":{"version":"2.0"},"accessors":[1],)"
                           R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
                           R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
  try {
    read_gltf(as_bytes(file), {});
    FAIL() << "read an accessor that is a number";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "accessor 0 is not an object");
  }
}

TEST(GltfLimits, AttributeCountsAndTypesAreCheckedBeforeDecoding) {
  const std::string file = primitives_naming_one_big_accessor(2000, 4096);
  size_t asked = 0;
  GltfReadOptions options;
  options.should_stop = [&] {
    ++asked;
    return false;
  };
  GltfAppearance look;
  const PolygonMesh mesh = read_gltf(as_bytes(file), options, nullptr, nullptr, &look);
  EXPECT_EQ(mesh.face_count(), 2000u);
  // The MAT4 accessor has 4096 elements, not POSITION's 3, and is no valid type for any
  // of the three: left out of every primitive.
  EXPECT_EQ(look.attribute("TEXCOORD_0"), nullptr);
  EXPECT_EQ(look.attribute("NORMAL"), nullptr);
  EXPECT_EQ(look.attribute("COLOR_0"), nullptr);
  // The valid one is kept, for every primitive.
  const GltfAppearance::Attribute* uv = look.attribute("TEXCOORD_1");
  ASSERT_NE(uv, nullptr);
  ASSERT_EQ(uv->values.size(), 2000u * 3 * 2);
  EXPECT_EQ(uv->values[2000 * 6 - 2], 0.0f);
  EXPECT_EQ(uv->values[2000 * 6 - 1], 1.0f);
  // The work done is the primitives' own: the stop callback is asked once per
  // StopCheck::kInterval elements handled, and decoding the MAT4 accessor 3 x 2000 times
  // would have been 393M of them (12,000 questions).
  EXPECT_LT(asked, 50u);
}

TEST(GltfLimits, AnAttributeOfTheRightCountButWrongTypeIsLeftOut) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  nlohmann::json& attributes = glb.json["meshes"][0]["primitives"][0]["attributes"];
  attributes["NORMAL"] = attributes["TEXCOORD_0"];  // VEC2: NORMAL must be VEC3
  GltfAppearance look;
  read_gltf(as_bytes(glb.bytes()), {}, nullptr, nullptr, &look);
  EXPECT_EQ(look.attribute("NORMAL"), nullptr);
  EXPECT_NE(look.attribute("TEXCOORD_0"), nullptr);
}

TEST(GltfLimits, AReadStopsWhenAsked) {
  const std::string file = primitives_naming_one_big_accessor(20000, 4);
  size_t asked = 0;
  GltfReadOptions options;
  options.should_stop = [&] { return ++asked >= 2; };
  try {
    read_gltf(as_bytes(file), options);
    FAIL() << "expected the read to stop";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped") << e.what();
  }
  EXPECT_EQ(asked, 2u);  // at the question that said stop, not at the end
}

TEST(GltfLimits, AWeldStopsWhenAsked) {
  const PolygonMesh mesh = testing::icosphere(5);
  PrepareOptions options;
  options.weld_tolerance = 1e-4;
  options.should_stop = [] { return true; };
  try {
    prepare_mesh(mesh, options);
    FAIL() << "expected the weld to stop";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped");
  }
  options.should_stop = [] { return false; };
  EXPECT_EQ(prepare_mesh(mesh, options).welded.mesh.vertex_count(), mesh.vertex_count());
}

TEST(GltfLimits, TheTopologyAnalysisStopsWhenAsked) {
  const PolygonMesh mesh = testing::icosphere(3);
  const std::function<bool()> stop_now = [] { return true; };
  const StopCheck stop(&stop_now);
  try {
    analyze_topology(mesh, &stop);
    FAIL() << "expected the analysis to stop";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped");
  }
  EXPECT_EQ(analyze_topology(mesh).genus(), 0);
}

TEST(GltfLimits, BaseColorPixelsCountEachDrawnImageOnce) {
  Glb glb(testing::textured_glb(testing::horseshoe()));
  // A second image naming the same bytes, a texture and an undrawn material using it, and
  // a third image (other bytes) used by no drawn material.
  glb.json["images"].push_back(glb.json["images"][0]);
  glb.json["textures"].push_back({{"source", 1}});
  nlohmann::json unused = glb.json["materials"][0];
  unused["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 1;
  glb.json["materials"].push_back(unused);
  GltfAppearance look;
  read_gltf(as_bytes(glb.bytes()), {}, nullptr, nullptr, &look);
  EXPECT_EQ(base_color_pixels(look), 16u * 16u);  // the 16 x 16 texture, once
  look.primitives[0].material = 1;                // drawn with the other material
  EXPECT_EQ(base_color_pixels(look), 16u * 16u);  // the same bytes: still once
  look.primitives[0].material = -1;
  EXPECT_EQ(base_color_pixels(look), 0u);  // nothing drawn with a texture
}

}  // namespace
}  // namespace spheremap
