#include "core/mesh/spatial_order.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace spheremap {
namespace {

// Spreads the low 21 bits of x to every third bit.
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

std::vector<uint32_t> morton_order(std::span<const Vec3> positions) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Vec3& p : positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
  const double scale = ((1 << 21) - 1) / extent;
  std::vector<std::pair<uint64_t, uint32_t>> keyed(positions.size());
  for (uint32_t v = 0; v < positions.size(); ++v) {
    const Vec3& p = positions[v];
    keyed[v] = {spread_bits(static_cast<uint64_t>((p.x - lo.x) * scale)) |
                    spread_bits(static_cast<uint64_t>((p.y - lo.y) * scale)) << 1 |
                    spread_bits(static_cast<uint64_t>((p.z - lo.z) * scale)) << 2,
                v};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(positions.size());
  for (size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
  return order;
}

std::vector<Triangle> canonical_triangles(std::span<const Triangle> triangles, size_t vertices) {
  // Each rotated to start at its smallest corner (same orientation), then a counting sort
  // on that corner, then each bucket (a vertex's few triangles) by the other two.
  auto rotated = [](const Triangle& t) -> Triangle {
    if (t[1] < t[0] && t[1] < t[2]) return {t[1], t[2], t[0]};
    if (t[2] < t[0] && t[2] < t[1]) return {t[2], t[0], t[1]};
    return t;
  };
  std::vector<uint32_t> start(vertices + 1, 0);
  for (const Triangle& t : triangles) ++start[rotated(t)[0] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<Triangle> out(triangles.size());
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (const Triangle& t : triangles) {
    const Triangle r = rotated(t);
    out[fill[r[0]]++] = r;
  }
  for (size_t v = 0; v < vertices; ++v)
    std::sort(out.begin() + start[v], out.begin() + start[v + 1]);
  return out;
}

PolygonMesh reordered(const PolygonMesh& mesh, const std::vector<uint32_t>& order) {
  PolygonMesh out;
  out.positions.resize(mesh.vertex_count());
  std::vector<uint32_t> new_id(mesh.vertex_count());
  for (uint32_t k = 0; k < order.size(); ++k) {
    out.positions[k] = mesh.positions[order[k]];
    new_id[order[k]] = k;
  }
  out.offsets = mesh.offsets;
  out.indices.resize(mesh.indices.size());
  for (size_t k = 0; k < mesh.indices.size(); ++k) out.indices[k] = new_id[mesh.indices[k]];
  return out;
}

}  // namespace spheremap
