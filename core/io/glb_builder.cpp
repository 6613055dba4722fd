#include "core/io/glb_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/mesh/input_error.h"

namespace spheremap {

size_t GlbBuilder::add_view(const std::string& data, int target) {
  nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", data.size()}};
  if (target) view["target"] = target;
  views_.push_back(std::move(view));
  bin_ += data;
  while (bin_.size() % 4) bin_.push_back('\0');
  return views_.size() - 1;
}

size_t GlbBuilder::add_accessor(nlohmann::json accessor, const std::string& data, int target) {
  accessor["bufferView"] = add_view(data, target);
  return add_accessor(std::move(accessor));
}

size_t GlbBuilder::add_accessor(nlohmann::json accessor) {
  accessors_.push_back(std::move(accessor));
  return accessors_.size() - 1;
}

nlohmann::json GlbBuilder::vec3_accessor(std::span<const Vec3> values, bool with_bounds) {
  nlohmann::json accessor = {{"componentType", 5126}, {"count", values.size()}, {"type", "VEC3"}};
  if (!with_bounds) return accessor;
  std::array<float, 3> lo, hi;  // of the float32 values, as glTF requires
  lo.fill(std::numeric_limits<float>::max());
  hi.fill(std::numeric_limits<float>::lowest());
  for (const Vec3& p : values)
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(p[k]);
      lo[k] = std::min(lo[k], f), hi[k] = std::max(hi[k], f);
    }
  accessor["min"] = lo, accessor["max"] = hi;
  return accessor;
}

namespace {

[[noreturn]] void throw_out_of_float32(double coordinate, const char* bound, const char* what) {
  char value[32];
  std::snprintf(value, sizeof value, "%.3g", coordinate);
  throw InputError("float32_range", std::string(what) + " (" + value + ") is " + bound +
                                        ", which glTF stores; write .obj, or scale the mesh");
}

double largest_coordinate(const Vec3& p) {
  return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

}  // namespace

void GlbBuilder::require_float32_positions(std::span<const Vec3> positions) {
  double largest = 0;
  for (const Vec3& p : positions) largest = std::max(largest, largest_coordinate(p));
  if (largest > std::numeric_limits<float>::max())
    throw_out_of_float32(largest, "beyond float32's range (3.4e38)", "a coordinate");
  if (largest > 0 && largest < std::numeric_limits<float>::min())
    throw_out_of_float32(largest, "below float32's smallest normal value (1.2e-38)",
                         "the largest coordinate");
}

size_t GlbBuilder::add_vec3(std::span<const Vec3> values, bool with_bounds, int target) {
  std::string data;
  data.reserve(values.size() * 12);
  for (const Vec3& p : values) {
    const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    // Past float32's range a coordinate becomes infinite: an invalid file, not a mesh (an
    // OBJ in units of 1e150 can be mapped, but its remesh cannot be stored as glTF).
    if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
      throw_out_of_float32(largest_coordinate(p), "beyond float32's range (3.4e38)",
                           "a coordinate");
    data.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  return add_accessor(vec3_accessor(values, with_bounds), data, target);
}

size_t GlbBuilder::add_floats(std::span<const float> values, int components, int target) {
  static const char* const kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
  const std::string data(reinterpret_cast<const char*>(values.data()), values.size() * 4);
  return add_accessor({{"componentType", 5126},
                       {"count", values.size() / static_cast<size_t>(components)},
                       {"type", kTypes[components]}},
                      data, target);
}

size_t GlbBuilder::add_indices(std::span<const std::array<uint32_t, 3>> triangles) {
  const std::string data(reinterpret_cast<const char*>(triangles.data()), triangles.size() * 12);
  return add_accessor(
      {{"componentType", 5125}, {"count", 3 * triangles.size()}, {"type", "SCALAR"}}, data,
      kElementArrayBuffer);
}

}  // namespace spheremap
