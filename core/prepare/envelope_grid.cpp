#include "core/prepare/envelope_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "core/mesh/input_error.h"
#include "core/mesh/triangle_tree.h"

namespace spheremap {

VoxelGrid layout_grid(const Vec3& lo, const Vec3& hi, double h, double d, size_t max_voxels) {
  if (!(h > 0) || !std::isfinite(h) || !(d >= 0) || !std::isfinite(d))
    throw InputError("envelope_size", "the envelope's voxel size and offset must be positive");
  VoxelGrid grid;
  grid.h = h;
  const double margin = d + kGridPadding * h;
  grid.origin = lo - Vec3{margin, margin, margin};
  std::array<double, 3> counts{};
  for (int a = 0; a < 3; ++a) counts[a] = std::ceil((hi[a] - lo[a] + 2 * margin) / h) + 1;
  const double voxels = counts[0] * counts[1] * counts[2];
  if (!(voxels <= double(max_voxels)) || counts[0] > 65535 || counts[1] > 65535 ||
      counts[2] > 65535)
    throw InputError("envelope_size", "the envelope's grid would have " + std::to_string(voxels) +
                                          " voxels, more than the cap of " +
                                          std::to_string(max_voxels) +
                                          ": use a lower envelope resolution");
  grid.nx = int(counts[0]), grid.ny = int(counts[1]), grid.nz = int(counts[2]);
  return grid;
}

namespace {

// Marks the voxels whose centre is within d of triangle abc. Columns run along the axis
// the triangle's normal is most aligned with, each limited to the slab |n.(p - a)| <= d.
// `magnitude` is the grid's largest absolute corner coordinate.
void mark_band(const VoxelGrid& g, const Vec3& a, const Vec3& b, const Vec3& c, double d,
               double magnitude, std::vector<uint8_t>& band, StopCheck& stop) {
  std::array<int, 3> lo{}, hi{};
  const std::array<int, 3> n_of{g.nx, g.ny, g.nz};
  std::array<double, 3> box_lo{}, box_hi{};  // the triangle's box
  for (int k = 0; k < 3; ++k) {
    box_lo[size_t(k)] = std::min({a[k], b[k], c[k]});
    box_hi[size_t(k)] = std::max({a[k], b[k], c[k]});
    magnitude = std::max({magnitude, std::abs(box_lo[size_t(k)]), std::abs(box_hi[size_t(k)])});
    const double mn = box_lo[size_t(k)] - d, mx = box_hi[size_t(k)] + d;
    lo[k] = std::max(0, int(std::floor((mn - g.origin[k]) / g.h - 0.5)));
    hi[k] = std::min(n_of[k] - 1, int(std::ceil((mx - g.origin[k]) / g.h - 0.5)));
    if (lo[k] > hi[k]) return;
  }
  Vec3 n = cross(b - a, c - a);
  // A triangle too thin for a plane (four nearly collinear points of pytorch3d's test OBJ)
  // has a normal of rounding noise: the columns are not cut to its plane, or the band
  // would follow that noise and miss most of the triangle (its wrap stood a third of the
  // diagonal off).
  const double length = too_thin_for_a_plane(b - a, c - a, dot(n, n)) ? 0 : norm(n);
  int w = 2;  // the column axis
  if (length > 0) {
    n = n * (1 / length);
    const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    w = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  }
  const int u = (w + 1) % 3, v = (w + 2) % 3;
  const double d2 = d * d;
  // A centre farther than d from the triangle's box is farther than d from the triangle,
  // and so is the point closest_on_triangle computes for it: that point lies in the box
  // up to rounding (TriangleTree's triangle-box skip rests on the same), a million times
  // less than this slack. Such centres (94% of those tested on a 97K-triangle horse) are
  // skipped without computing the point; the same voxels are marked.
  const double within = d + 1e-10 * magnitude, within2 = within * within;
  const auto gap = [&](int k, double x) {
    return std::max(std::max(box_lo[size_t(k)] - x, 0.0), x - box_hi[size_t(k)]);
  };
  const std::array<size_t, 3> stride{1, size_t(g.nx), size_t(g.nx) * size_t(g.ny)};
  double Vec3::*const along = w == 0 ? &Vec3::x : (w == 1 ? &Vec3::y : &Vec3::z);
  std::array<int, 3> cell{};
  for (cell[u] = lo[u]; cell[u] <= hi[u]; ++cell[u])
    for (cell[v] = lo[v]; cell[v] <= hi[v]; ++cell[v]) {
      int first = lo[w], last = hi[w];
      if (length > 0 && std::abs(n[w]) > 1e-3) {
        // n.(p - a) = 0 at p[w] = s; |n.(p - a)| <= d within d / |n[w]| of it.
        const double pu = g.origin[u] + (cell[u] + 0.5) * g.h;
        const double pv = g.origin[v] + (cell[v] + 0.5) * g.h;
        const double s = a[w] - (n[u] * (pu - a[u]) + n[v] * (pv - a[v])) / n[w];
        const double reach = d / std::abs(n[w]);
        first = std::max(first, int(std::floor((s - reach - g.origin[w]) / g.h - 0.5)));
        last = std::min(last, int(std::ceil((s + reach - g.origin[w]) / g.h - 0.5)));
      }
      if (first > last) continue;
      const double gu = gap(u, g.origin[u] + (cell[u] + 0.5) * g.h),
                   gv = gap(v, g.origin[v] + (cell[v] + 0.5) * g.h);
      const double lateral2 = gu * gu + gv * gv;
      if (lateral2 > within2) continue;
      // Walked by index and one coordinate: indexing through cell[] each voxel stalled on
      // store forwarding (a quarter of the band's time). The same voxels and centres.
      cell[w] = first;
      const Vec3 start = g.center(cell[0], cell[1], cell[2]);
      size_t i = g.index(cell[0], cell[1], cell[2]);
      for (int k = first; k <= last; ++k, i += stride[w]) {
        stop.tick();
        if (band[i]) continue;
        Vec3 p = start;
        p.*along = g.origin[w] + (k + 0.5) * g.h;
        const double gw = gap(w, p.*along);
        if (lateral2 + gw * gw > within2) continue;
        if (squared_norm(closest_on_triangle(p, a, b, c) - p) <= d2) band[i] = 1;
      }
    }
}

}  // namespace

std::vector<uint8_t> band_voxels(const VoxelGrid& g, std::span<const Vec3> positions,
                                 std::span<const Triangle> triangles, double d, StopCheck& stop) {
  std::vector<uint8_t> band(g.size(), 0);
  const Vec3 far = g.origin + Vec3{g.nx * g.h, g.ny * g.h, g.nz * g.h};
  double magnitude = 0;
  for (int k = 0; k < 3; ++k)
    magnitude = std::max({magnitude, std::abs(g.origin[k]), std::abs(far[k])});
  for (const Triangle& t : triangles) {
    const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) continue;
    mark_band(g, a, b, c, d, magnitude, band, stop);
  }
  return band;
}

std::vector<uint8_t> solid_voxels(const VoxelGrid& g, std::span<const Vec3> positions,
                                  std::span<const Triangle> triangles, double d, StopCheck& stop) {
  std::vector<uint8_t> solid = band_voxels(g, positions, triangles, d, stop);
  fill_enclosed(g, solid, stop);
  return solid;
}

void fill_enclosed(const VoxelGrid& g, std::vector<uint8_t>& solid, StopCheck& stop) {
  // The outside: a 6-connected flood fill of the non-band voxels from the border, by runs
  // along x: each open voxel found takes its whole open run at once, and a run's
  // neighbouring rows (above, below, in front, behind) are scanned over its extent. The
  // same voxels as a fill voxel by voxel, whose pops (a cache miss per neighbour) took 4%
  // of a horse envelope's profile; this reads rows in memory order (1%). The stack holds
  // runs, each once (runs in a row are apart: at most one per two voxels).
  std::vector<uint8_t> outside(g.size(), 0);
  std::vector<std::pair<uint32_t, uint32_t>> stack;  // first and last voxel of filled runs
  const size_t nx = size_t(g.nx), sy = nx, sz = nx * size_t(g.ny);
  const auto open = [&](size_t i) { return !solid[i] && !outside[i]; };
  // Fills the open run through voxel i (open) and pushes it.
  const auto take = [&](size_t i) {
    const size_t row = i - i % nx;
    size_t lo = i, hi = i;
    while (lo > row && open(lo - 1)) --lo;
    while (hi + 1 < row + nx && open(hi + 1)) ++hi;
    stop.tick(hi - lo + 1);
    std::fill(outside.begin() + std::ptrdiff_t(lo), outside.begin() + std::ptrdiff_t(hi) + 1,
              uint8_t{1});
    stack.push_back({uint32_t(lo), uint32_t(hi)});
  };
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x)
        if (x == 0 || y == 0 || z == 0 || x == g.nx - 1 || y == g.ny - 1 || z == g.nz - 1)
          if (open(g.index(x, y, z))) take(g.index(x, y, z));
  while (!stack.empty()) {
    // Plain copies: clang 14 (the fuzzers' compiler) cannot capture structured bindings.
    const size_t lo = stack.back().first, hi = stack.back().second;
    stack.pop_back();
    const size_t row = lo - lo % nx, y = row / nx % size_t(g.ny), z = row / sz;
    const auto scan = [&](size_t from) {  // the neighbouring row's voxels under [lo, hi]
      for (size_t j = from; j <= from + (hi - lo); ++j)
        if (open(j)) take(j);
    };
    if (y > 0) scan(lo - sy);
    if (y + 1 < size_t(g.ny)) scan(lo + sy);
    if (z > 0) scan(lo - sz);
    if (z + 1 < size_t(g.nz)) scan(lo + sz);
  }
  for (size_t i = 0; i < solid.size(); ++i) solid[i] = !outside[i];
}

namespace {

// The breadth-first search from the voxels of `from` next to the other kind (the grid's
// border left out).
std::vector<uint16_t> steps_by_search(const VoxelGrid& g, const std::vector<uint8_t>& inside,
                                      uint8_t from, StopCheck& stop) {
  std::vector<uint16_t> steps(g.size(), 0);
  std::vector<uint32_t> front, next;
  const size_t sx = 1, sy = size_t(g.nx), sz = size_t(g.nx) * size_t(g.ny);
  // Step 1: the voxels of `from` with a face neighbour of the other kind.
  for (int z = 1; z + 1 < g.nz; ++z)
    for (int y = 1; y + 1 < g.ny; ++y)
      for (int x = 1; x + 1 < g.nx; ++x) {
        const size_t i = g.index(x, y, z);
        stop.tick();
        if (inside[i] != from) continue;
        for (size_t j : {i - sx, i + sx, i - sy, i + sy, i - sz, i + sz})
          if (inside[j] != from) {
            steps[i] = 1, front.push_back(uint32_t(i));
            break;
          }
      }
  uint16_t level = 1;
  while (!front.empty()) {
    next.clear();
    const uint16_t following = level == 65535 ? level : uint16_t(level + 1);
    for (const uint32_t i : front) {
      stop.tick();
      const int x = int(i % sy), y = int((i / sy) % size_t(g.ny)), z = int(i / sz);
      for (const auto& [ok, j] : {std::pair{x > 0, i - sx}, std::pair{x + 1 < g.nx, i + sx},
                                  std::pair{y > 0, i - sy}, std::pair{y + 1 < g.ny, i + sy},
                                  std::pair{z > 0, i - sz}, std::pair{z + 1 < g.nz, i + sz}})
        if (ok && inside[j] == from && steps[j] == 0)
          steps[j] = following, next.push_back(uint32_t(j));
    }
    front.swap(next);
    level = following;
  }
  return steps;
}

// Whether a voxel of `from` on the grid's border has a face neighbour of the other kind
// (the search does not start from those; the envelope's padding keeps the solid off the
// border, so this is for grids made otherwise).
bool border_meets_other(const VoxelGrid& g, const std::vector<uint8_t>& inside, uint8_t from) {
  const std::array<int, 3> n{g.nx, g.ny, g.nz};
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y) {
      const bool face = z == 0 || y == 0 || z == g.nz - 1 || y == g.ny - 1;
      for (int x = 0; x < g.nx; x += face || x == g.nx - 1 ? 1 : g.nx - 1) {
        if (inside[g.index(x, y, z)] != from) continue;
        const std::array<int, 3> c{x, y, z};
        for (int a = 0; a < 3; ++a)
          for (const int side : {-1, 1}) {
            std::array<int, 3> m = c;
            m[size_t(a)] += side;
            if (m[size_t(a)] < 0 || m[size_t(a)] >= n[size_t(a)]) continue;
            if (inside[g.index(m[0], m[1], m[2])] != from) return true;
          }
      }
    }
  return false;
}

// a + 1, staying at 65535 (the cap, and "none yet").
inline uint16_t step_on(uint16_t a) {
  return uint16_t(a + (a != 65535));
}

}  // namespace

std::vector<uint16_t> steps_to_other(const VoxelGrid& g, const std::vector<uint8_t>& inside,
                                     uint8_t from, StopCheck& stop) {
  // The search's answer is the 6-step (L1) distance to the nearest voxel of the other kind:
  // a monotone path from a voxel to its L1-nearest other voxel meets no other voxel before
  // it (that one would be nearer), and each search step changes the L1 distance by one. So
  // unless the search's start leaves out a border voxel next to the other kind, the
  // separable L1 transform below (three axes, two sweeps each, in memory order) gives the
  // same numbers: 1.6% of a horse envelope's profile, where the search (a cache miss per
  // neighbour) took 6%.
  if (border_meets_other(g, inside, from)) return steps_by_search(g, inside, from, stop);
  if (std::find_if(inside.begin(), inside.end(), [&](uint8_t v) { return v != from; }) ==
      inside.end())
    return std::vector<uint16_t>(g.size(), 0);  // no other voxel: the search finds nothing
  std::vector<uint16_t> steps(g.size());
  for (size_t i = 0; i < steps.size(); ++i) steps[i] = inside[i] == from ? 65535 : 0;
  const size_t nx = size_t(g.nx), sy = nx, sz = nx * size_t(g.ny);
  // Along x, row by row.
  for (size_t row = 0; row < steps.size(); row += nx) {
    stop.tick(nx);
    uint16_t* s = &steps[row];
    for (size_t x = 1; x < nx; ++x) s[x] = std::min(s[x], step_on(s[x - 1]));
    for (size_t x = nx - 1; x-- > 0;) s[x] = std::min(s[x], step_on(s[x + 1]));
  }
  // Along y and z: each row against the row before (then after) it, x innermost.
  const auto sweep = [&](size_t stride, size_t length, size_t planes, size_t plane) {
    for (size_t p = 0; p < planes; ++p) {
      uint16_t* base = &steps[p * plane];
      for (size_t k = 1; k < length; ++k) {
        stop.tick(stride);
        uint16_t* s = base + k * stride;
        const uint16_t* before = s - stride;  // not s[i - stride]: i - stride wraps
        for (size_t i = 0; i < stride; ++i) s[i] = std::min(s[i], step_on(before[i]));
      }
      for (size_t k = length - 1; k-- > 0;) {
        stop.tick(stride);
        uint16_t* s = base + k * stride;
        const uint16_t* after = s + stride;
        for (size_t i = 0; i < stride; ++i) s[i] = std::min(s[i], step_on(after[i]));
      }
    }
  };
  sweep(sy, size_t(g.ny), size_t(g.nz), sz);
  sweep(sz, size_t(g.nz), 1, steps.size());
  return steps;
}

}  // namespace spheremap
