#include "core/outputs/normal_bake.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "core/io/png_writer.h"
#include "core/mesh/barycentric.h"
#include "core/mesh/parallel.h"
#include "core/mesh/parallel_stop.h"
#include "core/mesh/sphere_geometry.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/sphere_locator.h"

namespace spheremap {
namespace {

// Positions hashed by their bits (-0 and +0 alike): corners at one position share a normal.
struct PositionHash {
  size_t operator()(const Vec3& p) const {
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      const double c = p[k] == 0 ? 0.0 : p[k];
      uint64_t bits;
      std::memcpy(&bits, &c, 8);
      h = (h ^ bits) * 1099511628211ull;
    }
    return static_cast<size_t>(h);
  }
};

// Per corner of `triangles` (3 t + k), the area-weighted normals of `triangles` summed over
// every corner at the same position (unit length; zero where no face with area touches
// it). O(triangles): a wrapped part of a large asset does not pay for the whole mesh.
std::vector<Vec3> smooth_corner_normals(const PolygonMesh& mesh,
                                        std::span<const Triangle> triangles) {
  std::unordered_map<Vec3, Vec3, PositionHash> sum;
  for (const Triangle& t : triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3 n = cross(mesh.positions[t[1]] - a, mesh.positions[t[2]] - a);
    for (uint32_t v : t) sum[mesh.positions[v]] += n;
  }
  std::vector<Vec3> out(3 * triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      out[3 * t + k] = normalized_or(sum[mesh.positions[triangles[t][k]]], Vec3{});
  return out;
}

// The 3x3 cofactor matrix of a column-major 4x4 transform's linear part, times the sign
// of its determinant: what turns a normal as the transform turns its surface (the inverse
// transpose up to a positive scale). Nothing for a singular or non-finite transform.
std::optional<std::array<Vec3, 3>> normal_matrix(const Matrix4& m) {
  const Vec3 c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
  const double det = dot(c0, cross(c1, c2));
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return std::nullopt;
  const double s = det > 0 ? 1 : -1;
  // inverse transpose = (columns c1 x c2, c2 x c0, c0 x c1) / det
  return std::array<Vec3, 3>{cross(c1, c2) * s, cross(c2, c0) * s, cross(c0, c1) * s};
}

// The tangent frame a viewer interpolates at the point `s` of the square: from the
// remesh triangle holding it (remesh.cpp's split of each quad), its corners' NORMAL and
// TANGENT, the tangent made orthogonal to the normal.
struct Frame {
  Vec3 t, b, n;
};
Frame remesh_frame(int n, const Vec2& s, std::span<const Vec3> normals,
                   std::span<const std::array<float, 4>> tangents) {
  const int side = n + 1;
  const double gx = (s[0] + 1) / 2 * n, gy = (s[1] + 1) / 2 * n;
  const int i = std::clamp(static_cast<int>(gx), 0, n - 1);
  const int j = std::clamp(static_cast<int>(gy), 0, n - 1);
  const double fx = gx - i, fy = gy - j;
  const uint32_t a = j * side + i, b = a + 1, c = a + side + 1, d = a + side;
  std::array<uint32_t, 3> corner;
  std::array<double, 3> weight;
  if ((2 * i + 1 - n) * (2 * j + 1 - n) > 0) {
    if (fx + fy <= 1)
      corner = {a, b, d}, weight = {1 - fx - fy, fx, fy};
    else
      corner = {b, c, d}, weight = {1 - fy, fx + fy - 1, 1 - fx};
  } else if (fx >= fy) {
    corner = {a, b, c}, weight = {1 - fx, fx - fy, fy};
  } else {
    corner = {a, c, d}, weight = {1 - fy, fx, fy - fx};
  }
  Vec3 frame_n, frame_t;
  double handed = 0;
  for (int k = 0; k < 3; ++k) {
    const auto& tk = tangents[corner[k]];
    frame_n += normals[corner[k]] * weight[k];
    frame_t += Vec3{tk[0], tk[1], tk[2]} * weight[k];
    handed += tk[3] * weight[k];
  }
  frame_n = normalized_or(frame_n, Vec3{0, 0, 1});
  frame_t = normalized_or(frame_t - frame_n * dot(frame_n, frame_t), tangent_frame(frame_n)[0]);
  return {frame_t, cross(frame_n, frame_t) * (handed < 0 ? -1.0 : 1.0), frame_n};
}

}  // namespace

std::vector<std::array<float, 4>> remesh_tangents(const OctahedralRemesh& remesh,
                                                  std::span<const Vec3> normals) {
  // Per triangle, dP/du and dP/dw, w = up in the texture (the square's v): summed per
  // sample, area-weighted as the formula leaves them.
  std::vector<Vec3> du(remesh.positions.size()), dw(remesh.positions.size());
  for (const Triangle& t : remesh.triangles) {
    const Vec3 e1 = remesh.positions[t[1]] - remesh.positions[t[0]];
    const Vec3 e2 = remesh.positions[t[2]] - remesh.positions[t[0]];
    const Vec2 &s0 = remesh.square[t[0]], &s1 = remesh.square[t[1]], &s2 = remesh.square[t[2]];
    const double u1 = s1[0] - s0[0], w1 = s1[1] - s0[1], u2 = s2[0] - s0[0], w2 = s2[1] - s0[1];
    const double det = u1 * w2 - u2 * w1;
    if (!(std::abs(det) > 0)) continue;
    const double sign = det > 0 ? 1 : -1;  // the grid's spacing cancels once normalized
    const Vec3 tu = (e1 * w2 - e2 * w1) * sign, tw = (e2 * u1 - e1 * u2) * sign;
    for (uint32_t v : t) du[v] += tu, dw[v] += tw;
  }
  std::vector<std::array<float, 4>> out(remesh.positions.size());
  for (size_t v = 0; v < out.size(); ++v) {
    const Vec3& n = normals[v];
    const Vec3 fallback = tangent_frame(normalized_or(n, Vec3{0, 0, 1}))[0];
    const Vec3 t = normalized_or(du[v] - n * dot(n, du[v]), fallback);
    const float w = dot(cross(n, t), dw[v]) < 0 ? -1.0f : 1.0f;
    out[v] = {static_cast<float>(t.x), static_cast<float>(t.y), static_cast<float>(t.z), w};
  }
  return out;
}

ShadingNormals::ShadingNormals(const OriginalSurface& original) : original_(original) {
  const PolygonMesh& mesh = *original.mesh;
  normal_ = smooth_corner_normals(mesh, original.triangles);
  const GltfAppearance* look = original.look;
  const GltfAppearance::Attribute* attribute = look ? look->attribute("NORMAL") : nullptr;
  if (!attribute || attribute->components != 3) return;
  // Each corner's vertex in its primitive's vertex range (disjoint: reading order).
  std::vector<uint32_t> by_first_vertex(look->primitives.size());
  std::iota(by_first_vertex.begin(), by_first_vertex.end(), 0u);
  std::stable_sort(by_first_vertex.begin(), by_first_vertex.end(), [&](uint32_t a, uint32_t b) {
    return look->primitives[a].first_vertex < look->primitives[b].first_vertex;
  });
  for (size_t t = 0; t < original.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = original.triangles[t][k];
      const auto after = std::upper_bound(
          by_first_vertex.begin(), by_first_vertex.end(), v,
          [&](uint32_t x, uint32_t p) { return x < look->primitives[p].first_vertex; });
      if (after == by_first_vertex.begin()) continue;
      const GltfAppearance::Primitive& p = look->primitives[*(after - 1)];
      if (v - p.first_vertex >= p.vertex_count || v >= mesh.vertex_count() || !p.has("NORMAL") ||
          size_t{3} * v + 2 >= attribute->values.size())
        continue;
      const auto turn = normal_matrix(p.world);
      if (!turn) continue;
      const float* a = &attribute->values[size_t{3} * v];
      const Vec3 unit =
          normalized_or((*turn)[0] * a[0] + (*turn)[1] * a[1] + (*turn)[2] * a[2], Vec3{});
      if (unit == Vec3{}) continue;
      normal_[3 * t + k] = unit;
      from_attribute_ = true;
    }
}

Vec3 ShadingNormals::at(uint32_t t, const std::array<double, 3>& w) const {
  const Triangle& c = original_.triangles[t];
  const Vec3 n = normal_[3 * t] * w[0] + normal_[3 * t + 1] * w[1] + normal_[3 * t + 2] * w[2];
  const auto& p = original_.mesh->positions;
  const Vec3 face = normalized_or(cross(p[c[1]] - p[c[0]], p[c[2]] - p[c[0]]), Vec3{0, 0, 1});
  return normalized_or(n, face);
}

std::optional<BakedNormals> bake_normals_closest(
    const OriginalSurface& original, const MappedMesh& mapped, std::span<const Triangle> oriented,
    const OctahedralRemesh& remesh, std::span<const Vec3> normals,
    std::span<const std::array<float, 4>> tangents, int size, int threads,
    const std::function<bool()>* should_stop, const SphereLocator* shared_locator) {
  const StopCheck stop(should_stop);
  const PolygonMesh& envelope = mapped.prepared.welded.mesh;
  if (!original.mesh || original.triangles.empty() || size <= 0 ||
      oriented.size() != envelope.face_count() || normals.size() != remesh.positions.size() ||
      tangents.size() != remesh.positions.size() || remesh.resolution < 2)
    return std::nullopt;
  const ShadingNormals shading(original);
  stop.check();
  const TriangleTree tree(original.mesh->positions, original.triangles);
  stop.check();
  std::optional<SphereLocator> own_locator;
  const SphereLocator& locator =
      shared_or_own_locator(shared_locator, own_locator, mapped.map.sphere, oriented);
  const int n = remesh.resolution;
  std::vector<uint16_t> rgb(static_cast<size_t>(size) * size * 3, 0);
  std::vector<char> missed(static_cast<size_t>(size) * size, 0);
  // Over texels, not rows (a few thousand rows stay under parallel_for's threshold); the
  // stop asked once a row.
  ParallelStop row_stop(should_stop, static_cast<size_t>(size));
  parallel_for(rgb.size() / 3, resolve_threads(threads), [&](size_t texel) {
    if (row_stop.skip(texel)) return;
    const size_t row = texel / static_cast<size_t>(size);
    const int column = static_cast<int>(texel % static_cast<size_t>(size));
    uint16_t* px = &rgb[texel * 3];
    px[0] = px[1] = 128, px[2] = 255;  // flat until a normal is found
    const Vec2 s{(2.0 * column + 1) / size - 1, 1 - (2.0 * row + 1) / size};
    const Frame frame = remesh_frame(n, s, normals, tangents);
    const SphereHit hit = locator.locate(octahedral_decode(s, remesh.frame));
    if (hit.triangle == UINT32_MAX) {
      missed[texel] = 1;
      return;
    }
    const Triangle& e = oriented[hit.triangle];
    Vec3 point;  // the envelope's point at the texel, as the colour bake takes it
    for (int k = 0; k < 3; ++k) point += envelope.positions[e[k]] * hit.barycentric[k];
    const TriangleTree::Closest closest = tree.closest(point);
    if (closest.squared_distance == std::numeric_limits<double>::max()) return;
    const Triangle& o = original.triangles[closest.triangle];
    const auto& p = original.mesh->positions;
    const Vec3 want =
        shading.at(closest.triangle, barycentric(closest.point, p[o[0]], p[o[1]], p[o[2]]));
    const Vec3 local{dot(want, frame.t), dot(want, frame.b), dot(want, frame.n)};
    for (int k = 0; k < 3; ++k)
      px[k] = static_cast<uint16_t>(std::lround(std::clamp((local[k] + 1) / 2, 0.0, 1.0) * 255));
  });
  row_stop.throw_if_stopped();
  BakedNormals out;
  out.size = size;
  out.unlocated_texels = static_cast<size_t>(std::count(missed.begin(), missed.end(), 1));
  out.from_attribute = shading.from_attribute();
  out.png = encode_png(size, size, 8, rgb);
  return out;
}

}  // namespace spheremap
