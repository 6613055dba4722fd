#include "tests/thin_shells.h"

#include <cmath>
#include <functional>

namespace spheremap::testing {
namespace {

// A value in [-0.5, 0.5) from (i, j, salt), the same on every platform (no std
// distribution, whose output the standard leaves to the library).
double jitter(uint32_t i, uint32_t j, uint32_t salt) {
  uint64_t h = (uint64_t{i} * 0x9E3779B1u) ^ (uint64_t{j} * 0x85EBCA77u) ^ (uint64_t{salt} << 32);
  h ^= h >> 33, h *= 0xFF51AFD7ED558CCDull, h ^= h >> 33, h *= 0xC4CEB9FE1A85EC53ull, h ^= h >> 33;
  return static_cast<double>(h >> 11) / static_cast<double>(uint64_t{1} << 53) - 0.5;
}

PolygonMesh sheet(const std::function<bool(double, double)>& inside, int n) {
  const auto id = [n](int i, int j) { return static_cast<uint32_t>(i * (n + 1) + j); };
  std::vector<Vec3> grid;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = -1 + (2 * i + 0.7 * jitter(i, j, 1)) / n;
      const double y = -1 + (2 * j + 0.7 * jitter(i, j, 2)) / n;
      grid.push_back({x, y, 0.7 * (x * x + y * y) + 0.06 * std::sin(6 * x) * std::cos(5 * y)});
    }
  PolygonMesh mesh;
  std::vector<uint32_t> used(grid.size(), UINT32_MAX);
  const auto keep = [&](uint32_t a, uint32_t b, uint32_t c) {
    const Vec3 centroid = (grid[a] + grid[b] + grid[c]) * (1.0 / 3);
    if (!inside(centroid.x, centroid.y)) return;
    std::array<uint32_t, 3> corners{a, b, c};
    for (uint32_t& v : corners) {
      if (used[v] == UINT32_MAX)
        used[v] = static_cast<uint32_t>(mesh.positions.size()), mesh.positions.push_back(grid[v]);
      v = used[v];
    }
    mesh.add_face(corners);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0)
        keep(a, b, c), keep(a, c, d);
      else
        keep(a, b, d), keep(b, c, d);
    }
  return mesh;
}

}  // namespace

std::vector<NamedMesh> open_sheets(int n) {
  const auto fingers = [](double x, double y) {
    const double lobe = std::max(0.0, std::cos(3.5 * std::atan2(y, x)));
    return std::hypot(x, y) < 0.55 + 0.4 * lobe * lobe * lobe;
  };
  const auto perforated = [](double x, double y) {
    if (std::hypot(x, y) > 0.95) return false;
    for (int k = 0; k < 12; ++k)
      if (std::hypot(x - 0.6 * std::cos(k * M_PI / 6), y - 0.6 * std::sin(k * M_PI / 6)) < 0.12)
        return false;
    for (int k = 0; k < 5; ++k) {
      const double a = k * 2 * M_PI / 5 + 0.3;
      if (std::hypot(x - 0.25 * std::cos(a), y - 0.25 * std::sin(a)) < 0.08) return false;
    }
    return true;
  };
  const auto spiral = [](double x, double y) {
    const double r = std::hypot(x, y);
    if (r > 0.95 || r < 0.05) return false;
    return std::fmod(r * 6 - std::atan2(y, x) / M_PI + 4, 2.0) < 1.2;
  };
  return {{"sheet_fingers", sheet(fingers, n)},
          {"sheet_perforated", sheet(perforated, n)},
          {"sheet_spiral", sheet(spiral, n)}};
}

}  // namespace spheremap::testing
