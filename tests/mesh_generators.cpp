#include "tests/mesh_generators.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "core/io/glb_writer.h"
#include "core/io/png_writer.h"
#include "core/mesh/weld.h"

namespace spheremap::testing {

std::array<int, 3> textured_glb_color(double u, double v) {
  const int x = std::clamp(static_cast<int>(u * 16), 0, 15) / 4;
  const int y = std::clamp(static_cast<int>(v * 16), 0, 15) / 4;
  static const std::array<int, 3> kColors[4] = {
      {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
  return kColors[(x + 2 * y) % 4];
}

std::string textured_glb(const PolygonMesh& mesh) {
  Vec3 lo = mesh.positions[0], hi = lo;
  for (const Vec3& p : mesh.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  GlbMesh glb;
  for (const Triangle& t : fan_triangulate(mesh).triangles) {
    const uint32_t base = static_cast<uint32_t>(glb.positions.size());
    for (uint32_t v : t) {
      const Vec3& p = mesh.positions[v];
      glb.positions.push_back(p);
      glb.texcoords.push_back(
          {static_cast<float>((p.x - lo.x) / extent), static_cast<float>((p.y - lo.y) / extent)});
    }
    glb.triangles.push_back({base, base + 1, base + 2});
  }
  std::vector<uint16_t> rgb;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c : textured_glb_color((x + 0.5) / 16, (y + 0.5) / 16))
        rgb.push_back(static_cast<uint16_t>(c));
  glb.base_color_png = encode_png(16, 16, 8, rgb);
  glb.material_name = "test squares";
  return format_glb(glb);
}

std::string instanced_glb(const PolygonMesh& mesh, size_t count) {
  GlbMesh glb;
  glb.positions = mesh.positions;
  glb.triangles = fan_triangulate(mesh).triangles;
  const std::string file = format_glb(glb);
  // Taken apart (a JSON chunk, then a BIN chunk: format_glb's layout), given the instances'
  // accessor and the node's extension, and put back together.
  uint32_t json_length, bin_length;
  std::memcpy(&json_length, file.data() + 12, 4);
  std::memcpy(&bin_length, file.data() + 20 + json_length, 4);
  nlohmann::json json = nlohmann::json::parse(file.substr(20, json_length));
  std::string bin = file.substr(28 + json_length, bin_length);
  const size_t side = static_cast<size_t>(std::ceil(std::sqrt(static_cast<double>(count))));
  const size_t at = bin.size();
  for (size_t i = 0; i < count; ++i) {
    const float t[3] = {3.0f * static_cast<float>(i % side), 3.0f * static_cast<float>(i / side),
                        0};
    bin.append(reinterpret_cast<const char*>(t), sizeof t);
  }
  json["bufferViews"].push_back(
      {{"buffer", 0}, {"byteOffset", at}, {"byteLength", bin.size() - at}});
  json["accessors"].push_back({{"bufferView", json["bufferViews"].size() - 1},
                               {"componentType", 5126},
                               {"count", count},
                               {"type", "VEC3"}});
  json["buffers"][0]["byteLength"] = bin.size();
  json["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] =
      json["accessors"].size() - 1;
  json["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  std::string text = json.dump();
  while (text.size() % 4) text.push_back(' ');
  std::string out;
  auto u32 = [&](size_t v) {
    const uint32_t value = static_cast<uint32_t>(v);
    out.append(reinterpret_cast<const char*>(&value), 4);
  };
  u32(0x46546C67), u32(2), u32(28 + text.size() + bin.size());
  u32(text.size()), u32(0x4E4F534A);
  out += text;
  u32(bin.size()), u32(0x004E4942);
  return out + bin;
}

PolygonMesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  PolygonMesh m;
  m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Triangle> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      m.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));
      return midpoint[key] = static_cast<uint32_t>(m.positions.size() - 1);
    };
    std::vector<Triangle> next;
    for (const Triangle& f : faces) {
      const uint32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.insert(next.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    faces.swap(next);
  }
  for (Vec3& p : m.positions) p *= 1.0 / norm(p);
  for (const Triangle& f : faces) m.add_face(f);
  return m;
}

PolygonMesh quad_cube(int n) {
  PolygonMesh m;
  std::map<std::tuple<int, int, int>, uint32_t> ids;
  auto vertex = [&](int i, int j, int k) {
    auto key = std::make_tuple(i, j, k);
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    m.positions.push_back({2.0 * i / n - 1, 2.0 * j / n - 1, 2.0 * k / n - 1});
    return ids[key] = static_cast<uint32_t>(m.positions.size() - 1);
  };
  // Each cube face: a fixed axis at 0 or n, two running axes chosen so normals point out.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          auto at = [&](int u, int v) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = u;
            c[(axis + 2) % 3] = v;
            return vertex(c[0], c[1], c[2]);
          };
          uint32_t q[4] = {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)};
          if (side == 0) std::swap(q[1], q[3]);
          m.add_face(q);
        }
  return m;
}

PolygonMesh capped_tube(int around, int along, double length) {
  PolygonMesh m;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const double a = 2 * M_PI * i / around;
      m.positions.push_back({std::cos(a), std::sin(a), length * j / along});
    }
  auto id = [&](int i, int j) { return static_cast<uint32_t>(j * around + (i % around)); };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      uint32_t q[4] = {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      m.add_face(q);
    }
  std::vector<uint32_t> bottom, top;
  for (int i = around - 1; i >= 0; --i) bottom.push_back(id(i, 0));
  for (int i = 0; i < around; ++i) top.push_back(id(i, along));
  m.add_face(bottom);
  m.add_face(top);
  return m;
}

PolygonMesh prism(std::span<const std::array<double, 2>> outline, double height, bool fan_caps) {
  PolygonMesh m;
  const auto n = static_cast<uint32_t>(outline.size());
  for (double z : {-height / 2, height / 2})
    for (const auto& [x, y] : outline) m.positions.push_back({x, y, z});
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    const uint32_t side[4] = {i, j, n + j, n + i};
    m.add_face(side);
  }
  if (!fan_caps) {
    std::vector<uint32_t> bottom, top;
    for (uint32_t i = n; i-- > 0;) bottom.push_back(i);
    for (uint32_t i = 0; i < n; ++i) top.push_back(n + i);
    m.add_face(bottom);
    m.add_face(top);
    return m;
  }
  Vec3 centre;
  for (const auto& [x, y] : outline) centre += Vec3{x, y, 0};
  centre = (1.0 / n) * centre;
  const auto low = static_cast<uint32_t>(m.positions.size());
  m.positions.push_back({centre.x, centre.y, -height / 2});
  m.positions.push_back({centre.x, centre.y, height / 2});
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    const uint32_t bottom[3] = {low, j, i}, top[3] = {low + 1, n + i, n + j};
    m.add_face(bottom);
    m.add_face(top);
  }
  return m;
}

PolygonMesh horseshoe() {
  PolygonMesh m = capped_tube(12, 30, 12);
  for (Vec3& p : m.positions) {
    const double angle = p.z / 12 * 1.7 * M_PI, radius = 3 + p.x;
    p = {radius * std::cos(angle), p.y, radius * std::sin(angle)};
  }
  return m;
}

// A plate of unit cells (cols x rows, `thickness` thick) with a through-hole at each cell
// of `holes`: quads on top, bottom and the walls, outward. Genus: the number of holes.
PolygonMesh plate_with_holes(int cols, int rows, const std::vector<std::pair<int, int>>& holes,
                             double thickness) {
  auto solid = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= cols || y >= rows) return false;
    return std::find(holes.begin(), holes.end(), std::pair{x, y}) == holes.end();
  };
  PolygonMesh m;
  std::map<std::tuple<int, int, int>, uint32_t> id;
  auto at = [&](int x, int y, int z) {
    const auto [it, added] = id.emplace(std::tuple{x, y, z}, uint32_t(m.positions.size()));
    if (added) m.positions.push_back({double(x), double(y), z * thickness});
    return it->second;
  };
  auto quad = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    const uint32_t q[4] = {a, b, c, d};
    m.add_face(q);
  };
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) {
      if (!solid(x, y)) continue;
      quad(at(x, y, 1), at(x + 1, y, 1), at(x + 1, y + 1, 1), at(x, y + 1, 1));  // top
      quad(at(x, y + 1, 0), at(x + 1, y + 1, 0), at(x + 1, y, 0), at(x, y, 0));  // bottom
      if (!solid(x, y - 1)) quad(at(x, y, 0), at(x + 1, y, 0), at(x + 1, y, 1), at(x, y, 1));
      if (!solid(x, y + 1))
        quad(at(x + 1, y + 1, 0), at(x, y + 1, 0), at(x, y + 1, 1), at(x + 1, y + 1, 1));
      if (!solid(x - 1, y)) quad(at(x, y + 1, 0), at(x, y, 0), at(x, y, 1), at(x, y + 1, 1));
      if (!solid(x + 1, y))
        quad(at(x + 1, y, 0), at(x + 1, y + 1, 0), at(x + 1, y + 1, 1), at(x + 1, y, 1));
    }
  return m;
}

PolygonMesh torus(int around, int along) {
  PolygonMesh m;
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const double u = 2 * M_PI * i / around, v = 2 * M_PI * j / along;
      m.positions.push_back(
          {(2 + std::cos(u)) * std::cos(v), (2 + std::cos(u)) * std::sin(v), std::sin(u)});
    }
  auto id = [&](int i, int j) {
    return static_cast<uint32_t>((j % along) * around + (i % around));
  };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      uint32_t q[4] = {id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)};
      m.add_face(q);
    }
  return m;
}

namespace {
void add_tetrahedron(PolygonMesh& m, Vec3 offset, uint32_t apex_id) {
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  for (Vec3 p : {Vec3{1, 1, 1}, Vec3{1, -1, -1}, Vec3{-1, 1, -1}, Vec3{-1, -1, 1}})
    m.positions.push_back(p + offset);
  uint32_t v[4] = {base, base + 1, base + 2, base + 3};
  if (apex_id != UINT32_MAX) {  // reuse an existing vertex instead of v[0]
    m.positions.erase(m.positions.begin() + base);
    v[0] = apex_id, v[1] = base, v[2] = base + 1, v[3] = base + 2;
  }
  const Triangle faces[4] = {
      {v[0], v[1], v[2]}, {v[0], v[3], v[1]}, {v[0], v[2], v[3]}, {v[1], v[3], v[2]}};
  for (const Triangle& f : faces) m.add_face(f);
}
}  // namespace

PolygonMesh two_tetrahedra() {
  PolygonMesh m;
  add_tetrahedron(m, {0, 0, 0}, UINT32_MAX);
  add_tetrahedron(m, {5, 0, 0}, UINT32_MAX);
  return m;
}

PolygonMesh pinched_tetrahedra() {
  PolygonMesh m;
  add_tetrahedron(m, {0, 0, 0}, UINT32_MAX);
  add_tetrahedron(m, {2, 2, 2}, 0);
  return m;
}

PolygonMesh cube_and_corner_tetrahedron(bool fin) {
  PolygonMesh m;
  for (int k = 0; k < 8; ++k)
    m.positions.push_back({double(k >> 2), double(k >> 1 & 1), double(k & 1)});
  const Triangle cube[12] = {{0, 6, 4}, {0, 2, 6}, {0, 3, 2}, {0, 1, 3}, {2, 7, 6}, {2, 3, 7},
                             {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}, {1, 5, 7}, {1, 7, 3}};
  for (const Triangle& t : cube) m.add_face(t);
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
    m.positions.push_back(p);
  const Triangle tetra[4] = {{8, 10, 9}, {8, 11, 10}, {9, 11, 8}, {9, 10, 11}};
  for (const Triangle& t : tetra) m.add_face(t);
  if (fin) {
    m.positions.push_back({2, 2, 0.5});
    m.add_face(Triangle{6, 7, 12});
  }
  return m;
}

PolygonMesh reversed(PolygonMesh mesh) {
  for (size_t f = 0; f < mesh.face_count(); ++f)
    std::reverse(mesh.indices.begin() + mesh.offsets[f],
                 mesh.indices.begin() + mesh.offsets[f + 1]);
  return mesh;
}

namespace {

// The faces of icosphere(levels) whose every corner passes `keep`, welded.
template <typename Keep>
PolygonMesh icosphere_faces(int levels, Keep keep) {
  const PolygonMesh sphere = icosphere(levels);
  PolygonMesh kept;
  kept.positions = sphere.positions;
  for (size_t f = 0; f < sphere.face_count(); ++f) {
    const auto face = sphere.face(f);
    if (std::all_of(face.begin(), face.end(),
                    [&](uint32_t v) { return keep(sphere.positions[v]); }))
      kept.add_face(face);
  }
  return weld(kept, 0).mesh;
}

}  // namespace

PolygonMesh dome(int levels) {
  return icosphere_faces(levels, [](const Vec3& p) { return p.z > 0; });
}

PolygonMesh band(int levels) {
  return icosphere_faces(levels, [](const Vec3& p) { return std::abs(p.z) < 0.6; });
}

PolygonMesh holed_torus(int around, int along) {
  const PolygonMesh whole = torus(around, along);
  PolygonMesh holed;
  holed.positions = whole.positions;
  // torus() makes the quad (i, j) the face j * around + i.
  for (size_t f = 0; f < whole.face_count(); ++f)
    if (f % around >= static_cast<size_t>(around / 4) ||
        f / around >= static_cast<size_t>(along / 4))
      holed.add_face(whole.face(f));
  return holed;
}

PolygonMesh moebius_band(int segments) {
  PolygonMesh out;
  for (int k = 0; k < segments; ++k) {
    const double t = 2 * M_PI * k / segments;
    const Vec3 centre{2 * std::cos(t), 2 * std::sin(t), 0};
    const Vec3 across =
        Vec3{std::cos(t), std::sin(t), 0} * std::cos(t / 2) + Vec3{0, 0, 1} * std::sin(t / 2);
    out.positions.push_back(centre - across * 0.5);  // a_k = 2k
    out.positions.push_back(centre + across * 0.5);  // b_k = 2k + 1
  }
  const auto n = static_cast<uint32_t>(segments);
  for (uint32_t k = 0; k + 1 < n; ++k)
    out.add_face(std::array{2 * k, 2 * k + 2, 2 * k + 3, 2 * k + 1});
  // Half a turn round, a_n is b_0 and b_n is a_0.
  out.add_face(std::array{2 * (n - 1), 1u, 0u, 2 * (n - 1) + 1});
  return out;
}

PolygonMesh quad_scatter(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 100);
  PolygonMesh out;
  for (int k = 0; k < count; ++k) {
    const double x = uniform(rng), y = uniform(rng), z = uniform(rng);
    const auto base = static_cast<uint32_t>(out.positions.size());
    for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}})
      out.positions.push_back({x + dx, y + 0.5 * dy, z + 0.3 * dx});
    out.add_face(std::array<uint32_t, 3>{base, base + 1, base + 2});
    out.add_face(std::array<uint32_t, 3>{base, base + 2, base + 3});
  }
  return out;
}

PolygonMesh assembled(const std::vector<std::pair<PolygonMesh, Vec3>>& parts) {
  PolygonMesh out;
  std::vector<uint32_t> corners;
  for (const auto& [mesh, offset] : parts) {
    const uint32_t base = static_cast<uint32_t>(out.vertex_count());
    for (const Vec3& p : mesh.positions) out.positions.push_back(p + offset);
    for (size_t f = 0; f < mesh.face_count(); ++f) {
      corners.clear();
      for (uint32_t v : mesh.face(f)) corners.push_back(base + v);
      out.add_face(corners);
    }
  }
  return out;
}

PolygonMesh without_face(const PolygonMesh& mesh, size_t skip) {
  PolygonMesh out;
  out.positions = mesh.positions;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (f != skip) out.add_face(mesh.face(f));
  return out;
}

PolygonMesh with_limbs(PolygonMesh base, std::span<const Vec3> directions, double length,
                       double thickness) {
  for (Vec3& p : base.positions) {
    double nearest = M_PI;
    for (const Vec3& d : directions)
      nearest = std::min(nearest, std::acos(std::clamp(dot(p, d) / norm(d), -1.0, 1.0)));
    const double radius =
        nearest > 0 ? std::clamp(thickness / nearest, 1.0, 1.0 + length) : 1.0 + length;
    p *= radius;
  }
  return base;
}

PolygonMesh swirled(PolygonMesh mesh, double radians_per_unit) {
  for (Vec3& p : mesh.positions) {
    const double angle = radians_per_unit * std::hypot(p.x, p.y);
    const double c = std::cos(angle), s = std::sin(angle);
    p = {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
  }
  return mesh;
}

PolygonMesh twisted(PolygonMesh mesh, double radians_per_unit) {
  for (Vec3& p : mesh.positions) {
    const double c = std::cos(radians_per_unit * p.z), s = std::sin(radians_per_unit * p.z);
    p = {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
  }
  return mesh;
}

PolygonMesh scaled(PolygonMesh mesh, const Vec3& factors) {
  for (Vec3& p : mesh.positions) p = {p.x * factors.x, p.y * factors.y, p.z * factors.z};
  return mesh;
}

PolygonMesh quad_sphere(int n) {
  PolygonMesh mesh = quad_cube(n);
  for (Vec3& p : mesh.positions) p *= 1.0 / norm(p);
  return mesh;
}

std::vector<NamedMesh> stress_meshes(bool with_million) {
  // A hand: five fingers in the xy plane 25 degrees apart, curled by the swirl.
  std::vector<Vec3> fingers;
  for (int k = -2; k <= 2; ++k) {
    const double a = k * 25.0 * M_PI / 180;
    fingers.push_back({std::cos(a), std::sin(a), 0});
  }
  // Spikes: 24 directions on a Fibonacci spiral.
  std::vector<Vec3> spikes;
  for (int k = 0; k < 24; ++k) {
    const double z = 1 - (2 * k + 1) / 24.0, r = std::sqrt(1 - z * z);
    const double a = k * M_PI * (3 - std::sqrt(5.0));
    spikes.push_back({r * std::cos(a), r * std::sin(a), z});
  }
  const std::vector<Vec3> axes = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  std::vector<NamedMesh> out;
  out.push_back({"stress_fingers", swirled(with_limbs(icosphere(6), fingers, 5, 0.1), 0.35)});
  out.push_back({"stress_spikes", with_limbs(icosphere(5), spikes, 3, 0.08)});
  out.push_back({"stress_blade", twisted(scaled(icosphere(5), {0.02, 0.6, 6}), 0.25)});
  out.push_back({"stress_quad_limbs", with_limbs(quad_sphere(48), axes, 4, 0.15)});
  out.push_back({"stress_long_tube", capped_tube(16, 600, 300)});
  // CAD parts: long side slivers between fans, and non-convex polygon caps.
  std::vector<std::array<double, 2>> circle, star;
  for (int k = 0; k < 256; ++k)
    circle.push_back({std::cos(2 * M_PI * k / 256), std::sin(2 * M_PI * k / 256)});
  for (int k = 0; k < 64; ++k) {
    const double r = k % 2 == 0 ? 1.0 : 0.1;
    star.push_back({r * std::cos(2 * M_PI * k / 64), r * std::sin(2 * M_PI * k / 64)});
  }
  out.push_back({"stress_cad_cylinder", prism(circle, 3, true)});
  out.push_back({"stress_cad_star", prism(star, 0.5, false)});
  if (with_million)
    out.push_back({"stress_fingers_1m", swirled(with_limbs(icosphere(8), fingers, 5, 0.1), 0.35)});
  return out;
}

std::vector<NamedMesh> random_stress_meshes(int count, unsigned seed) {
  std::mt19937 rng(seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  std::normal_distribution<double> gaussian;
  std::vector<NamedMesh> out;
  for (int k = 0; k < count; ++k) {
    std::vector<Vec3> limbs(static_cast<size_t>(uniform(1, 31)));
    for (Vec3& d : limbs) {
      d = {gaussian(rng), gaussian(rng), gaussian(rng)};
      d = d * (1 / norm(d));
    }
    const double base = uniform(0, 3);
    PolygonMesh mesh = with_limbs(base < 1   ? icosphere(4)
                                  : base < 2 ? quad_sphere(24)
                                             : icosphere(5),
                                  limbs, uniform(0.5, 10), uniform(0.03, 0.25));
    mesh = swirled(std::move(mesh), uniform(-0.6, 0.6));
    mesh = twisted(std::move(mesh), uniform(-0.3, 0.3));
    mesh = scaled(std::move(mesh), {uniform(0.3, 1.5), uniform(0.3, 1.5), uniform(0.3, 1.5)});
    out.push_back({"random_" + std::to_string(seed) + "_" + std::to_string(k), std::move(mesh)});
  }
  return out;
}

}  // namespace spheremap::testing
