// GLB files taken apart and put back together, for tests that mutate them.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "core/io/glb_writer.h"
#include "core/io/gltf_reader.h"
#include "core/mesh/input_error.h"
#include "core/mesh/mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap::testing {

inline std::span<const uint8_t> as_bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// `bytes` in base64, for data: URIs.
inline std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = static_cast<uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<uint8_t>(bytes[i + 2]);
    out += kAlphabet[n >> 18 & 63];
    out += kAlphabet[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kAlphabet[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

// A GLB split into its JSON and its binary chunk, to mutate and put back together.
struct Glb {
  nlohmann::json json;
  std::string bin;

  explicit Glb(const std::string& file) {
    uint32_t json_length;
    std::memcpy(&json_length, file.data() + 12, 4);
    json = nlohmann::json::parse(file.substr(20, json_length));
    const size_t bin_at = 20 + json_length;
    if (bin_at + 8 <= file.size()) {
      uint32_t bin_length;
      std::memcpy(&bin_length, file.data() + bin_at, 4);
      bin = file.substr(bin_at + 8, bin_length);
    }
  }
  std::string bytes() const {
    std::string text = json.dump();
    while (text.size() % 4) text.push_back(' ');
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67), u32(2), u32(static_cast<uint32_t>(28 + text.size() + bin.size()));
    u32(static_cast<uint32_t>(text.size())), u32(0x4E4F534A);
    out += text;
    u32(static_cast<uint32_t>(bin.size())), u32(0x004E4942);
    return out + bin;
  }
};

inline std::string sphere_glb() {
  const PolygonMesh m = testing::icosphere(1);
  GlbMesh glb;
  glb.positions = glb.normals = m.positions;
  glb.triangles = fan_triangulate(m).triangles;
  glb.extras = {{"note", "test"}};
  return format_glb(glb);
}

// The message of the InputError(`check`) reading `bytes` raises (a test failure if none).
inline std::string read_error(const std::string& bytes, const char* check = "gltf") {
  try {
    read_gltf(as_bytes(bytes));
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), check);
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

// A textured horseshoe whose bin also holds `image_bytes` of a PNG-looking image (its
// signature, then zeros: enough for the reader, which only sniffs the type), named by
// `references` more images.
inline std::string many_images_naming_one_view(size_t image_bytes, size_t references) {
  Glb glb(textured_glb(horseshoe()));
  std::string image = "\x89PNG\r\n\x1a\n";
  image.resize(image_bytes, '\0');
  while (glb.bin.size() % 4) glb.bin.push_back('\0');
  const size_t view = glb.json["bufferViews"].size();
  glb.json["bufferViews"].push_back(
      {{"buffer", 0}, {"byteOffset", glb.bin.size()}, {"byteLength", image.size()}});
  glb.bin += image;
  glb.json["buffers"][0]["byteLength"] = glb.bin.size();
  for (size_t i = 0; i < references; ++i)
    glb.json["images"].push_back({{"bufferView", view}, {"mimeType", "image/png"}});
  return glb.bytes();
}

// `primitives` one-triangle primitives, each naming accessor 1 (a MAT4 float accessor of
// `big_count` elements) as TEXCOORD_0, NORMAL and COLOR_0, and accessor 2 (VEC2 float,
// 3 elements: a valid TEXCOORD_1) shared by all of them.
inline std::string primitives_naming_one_big_accessor(size_t primitives, size_t big_count) {
  Glb glb(sphere_glb());
  const float triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const float uv[6] = {0, 0, 1, 0, 0, 1};
  std::string bin(reinterpret_cast<const char*>(triangle), sizeof triangle);
  bin.append(reinterpret_cast<const char*>(uv), sizeof uv);
  const size_t big_at = bin.size();
  bin.resize(big_at + big_count * 64, '\0');
  glb.bin = bin;
  glb.json["buffers"] = {{{"byteLength", bin.size()}}};
  glb.json["bufferViews"] = {
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
      {{"buffer", 0}, {"byteOffset", big_at}, {"byteLength", big_count * 64}},
      {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 24}}};
  glb.json["accessors"] = {
      {{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
      {{"bufferView", 1}, {"componentType", 5126}, {"count", big_count}, {"type", "MAT4"}},
      {{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}}};
  nlohmann::json list = nlohmann::json::array();
  for (size_t p = 0; p < primitives; ++p)
    list.push_back(
        {{"attributes",
          {{"POSITION", 0}, {"TEXCOORD_0", 1}, {"NORMAL", 1}, {"COLOR_0", 1}, {"TEXCOORD_1", 2}}}});
  glb.json["meshes"] = {{{"primitives", list}}};
  glb.json["nodes"] = {{{"mesh", 0}}};
  glb.json["scenes"] = {{{"nodes", {0}}}};
  glb.json["scene"] = 0;
  return glb.bytes();
}

}  // namespace spheremap::testing
