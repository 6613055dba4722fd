#include "core/io/glb_writer.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace spheremap {
namespace {

void append_bytes(std::string& out, const void* data, size_t size) {
  out.append(static_cast<const char*>(data), size);
}

void append_u32(std::string& out, uint32_t v) {
  append_bytes(out, &v, 4);
}

// Appends float32 xyz triples; returns {min, max} per axis of what was written.
std::pair<std::array<float, 3>, std::array<float, 3>> append_vec3(std::string& bin,
                                                                  const std::vector<Vec3>& v) {
  std::array<float, 3> lo, hi;
  lo.fill(std::numeric_limits<float>::max());
  hi.fill(std::numeric_limits<float>::lowest());
  for (const Vec3& p : v) {
    const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    append_bytes(bin, f, sizeof f);
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], f[k]), hi[k] = std::max(hi[k], f[k]);
  }
  return {lo, hi};
}

}  // namespace

std::string format_glb(const GlbMesh& mesh) {
  std::string bin;
  nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
  const size_t n = mesh.positions.size();
  auto add_view = [&](size_t offset, size_t length, int target) {
    views.push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}});
    return views.size() - 1;
  };
  // POSITION
  size_t offset = bin.size();
  auto [lo, hi] = append_vec3(bin, mesh.positions);
  accessors.push_back({{"bufferView", add_view(offset, bin.size() - offset, 34962)},
                       {"componentType", 5126},
                       {"count", n},
                       {"type", "VEC3"},
                       {"min", lo},
                       {"max", hi}});
  nlohmann::json attributes = {{"POSITION", 0}};
  if (!mesh.normals.empty()) {
    offset = bin.size();
    append_vec3(bin, mesh.normals);
    accessors.push_back({{"bufferView", add_view(offset, bin.size() - offset, 34962)},
                         {"componentType", 5126},
                         {"count", n},
                         {"type", "VEC3"}});
    attributes["NORMAL"] = accessors.size() - 1;
  }
  offset = bin.size();
  for (const Triangle& t : mesh.triangles) append_bytes(bin, t.data(), 12);
  accessors.push_back({{"bufferView", add_view(offset, bin.size() - offset, 34963)},
                       {"componentType", 5125},
                       {"count", 3 * mesh.triangles.size()},
                       {"type", "SCALAR"}});
  const nlohmann::json primitive = {
      {"attributes", attributes}, {"indices", accessors.size() - 1}, {"mode", 4}};
  while (bin.size() % 4) bin.push_back('\0');
  const nlohmann::json json = {
      {"asset", {{"version", "2.0"}, {"generator", "spheremap"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes", {{{"primitives", {primitive}}, {"extras", mesh.extras}}}},
      {"accessors", accessors},
      {"bufferViews", views},
      {"buffers", {{{"byteLength", bin.size()}}}},
  };
  std::string text = json.dump();
  while (text.size() % 4) text.push_back(' ');
  std::string out;
  out.reserve(28 + text.size() + bin.size());
  append_u32(out, 0x46546C67);
  append_u32(out, 2);
  append_u32(out, static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  append_u32(out, static_cast<uint32_t>(text.size()));
  append_u32(out, 0x4E4F534A);
  out += text;
  append_u32(out, static_cast<uint32_t>(bin.size()));
  append_u32(out, 0x004E4942);
  out += bin;
  return out;
}

}  // namespace spheremap
