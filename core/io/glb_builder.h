// The binary chunk of a GLB under construction: bufferViews and accessors appended as
// their data is, each view 4-byte aligned. Shared by the GLB writers.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/mesh/vec3.h"

namespace spheremap {

class GlbBuilder {
 public:
  static constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

  // A bufferView over `data` (target 0: none); returns its index.
  size_t add_view(const std::string& data, int target = 0);
  // An accessor over a new view of `data`; returns its index.
  size_t add_accessor(nlohmann::json accessor, const std::string& data, int target = 0);
  // An accessor with no data in this buffer (Draco decodes it).
  size_t add_accessor(nlohmann::json accessor);

  // float32 VEC3: the accessor's description (min/max with_bounds), and one over new data.
  static nlohmann::json vec3_accessor(std::span<const Vec3> values, bool with_bounds);
  size_t add_vec3(std::span<const Vec3> values, bool with_bounds, int target = kArrayBuffer);
  size_t add_floats(std::span<const float> values, int components, int target = kArrayBuffer);
  size_t add_indices(std::span<const std::array<uint32_t, 3>> triangles);

  // Throws InputError "float32_range" when a mesh's positions cannot be stored as float32:
  // a coordinate past its range (it would be infinite), or every coordinate below its
  // smallest normal value (1.2e-38: the mesh would be stored as a point or in a few
  // subnormal steps). add_vec3 refuses the first for any data.
  static void require_float32_positions(std::span<const Vec3> positions);

  nlohmann::json& views() { return views_; }
  nlohmann::json& accessors() { return accessors_; }
  std::string& bin() { return bin_; }

 private:
  std::string bin_;
  nlohmann::json views_ = nlohmann::json::array(), accessors_ = nlohmann::json::array();
};

}  // namespace spheremap
