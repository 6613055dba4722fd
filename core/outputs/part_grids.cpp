#include "core/outputs/part_grids.h"

#include <algorithm>
#include <cmath>

namespace spheremap {
namespace {

// Each part's grid at `scale` times the area rule, no smaller than `floor`.
std::vector<int> scaled_grids(int resolution, std::span<const double> shares, double scale,
                              int floor) {
  std::vector<int> grids(shares.size());
  for (size_t k = 0; k < shares.size(); ++k) {
    const int even = static_cast<int>(std::lround(resolution * scale * shares[k] / 2)) * 2;
    grids[k] = std::clamp(even, std::min(floor, resolution), resolution);
  }
  return grids;
}

double samples(const std::vector<int>& grids) {
  double total = 0;
  for (int grid : grids) total += static_cast<double>(grid + 1) * (grid + 1);
  return total;
}

}  // namespace

std::vector<int> part_grids(int resolution, std::span<const double> areas,
                            std::span<const double> diagonals) {
  double largest = 0, longest = 0;
  for (double area : areas) largest = std::max(largest, area);
  for (double diagonal : diagonals) longest = std::max(longest, diagonal);
  std::vector<double> shares(areas.size(), 1.0);
  if (largest > 0)
    for (size_t k = 0; k < areas.size(); ++k) {
      shares[k] = std::sqrt(areas[k] / largest);
      if (longest > 0 && k < diagonals.size())
        shares[k] = std::max(shares[k], diagonals[k] / longest);
    }
  const double budget = kPartSampleBudget * (resolution + 1.0) * (resolution + 1.0);
  std::vector<int> grids = scaled_grids(resolution, shares, 1, 8);
  if (samples(grids) <= budget) return grids;
  // The largest scale whose grids fit (samples only grow with the scale): bisection.
  double fits = 0, too_large = 1;
  for (int step = 0; step < 50; ++step) {
    const double middle = (fits + too_large) / 2;
    (samples(scaled_grids(resolution, shares, middle, 2)) <= budget ? fits : too_large) = middle;
  }
  return scaled_grids(resolution, shares, fits, 2);
}

int remesh_texture_size(int resolution) {
  return std::clamp(2 * resolution, 256, 2048);
}

int part_texture_size(int resolution, int grid) {
  const int whole = remesh_texture_size(resolution);
  const long scaled = std::lround(static_cast<double>(whole) * grid / std::max(resolution, 1));
  return static_cast<int>(std::clamp<long>(scaled, kMinPartTexture, whole));
}

}  // namespace spheremap
