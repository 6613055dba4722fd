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

// The message of the InputError("gltf") reading `bytes` raises (a test failure if none).
inline std::string read_error(const std::string& bytes) {
  try {
    read_gltf(as_bytes(bytes));
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "gltf");
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

}  // namespace spheremap::testing
