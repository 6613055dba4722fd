// The envelope (core/prepare/envelope*.h, Reach II): any triangles -> one closed,
// 2-manifold, genus-0 mesh around them that maps certified; the simple-point test checked
// against an independent count; sizes past the cap and the stop callback refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/input_error.h"
#include "core/mesh/topology.h"
#include "core/mesh/triangle_tree.h"
#include "core/mesh/weld.h"
#include "core/prepare/envelope.h"
#include "core/prepare/envelope_check.h"
#include "core/prepare/envelope_grid.h"
#include "core/prepare/envelope_topology.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// --- the simple-point test against an independent count ---------------------------------

using Cube = std::array<int, 27>;  // 1 in the set; index x + 3y + 9z, centre 13

// Components of the voxels of `cube` equal to `kind` among `cells`, by coordinate BFS.
int components(const Cube& cube, int kind, const std::vector<int>& cells, bool six,
               bool touch_centre) {
  std::set<int> left(cells.begin(), cells.end());
  std::erase_if(left, [&](int c) { return cube[size_t(c)] != kind; });
  int count = 0;
  while (!left.empty()) {
    std::vector<int> stack = {*left.begin()};
    left.erase(left.begin());
    bool touches = false;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      const int cx = c % 3 - 1, cy = c / 3 % 3 - 1, cz = c / 9 - 1;
      touches |= std::abs(cx) + std::abs(cy) + std::abs(cz) == 1;
      for (auto it = left.begin(); it != left.end();) {
        const int dx = std::abs(*it % 3 - 1 - cx), dy = std::abs(*it / 3 % 3 - 1 - cy),
                  dz = std::abs(*it / 9 - 1 - cz);
        const bool adjacent = six ? dx + dy + dz == 1 : std::max({dx, dy, dz}) == 1;
        if (adjacent) {
          stack.push_back(*it);
          it = left.erase(it);
        } else {
          ++it;
        }
      }
    }
    if (!touch_centre || touches) ++count;
  }
  return count;
}

// Euler characteristic of the union of the closed unit cubes of the set.
long euler_characteristic(const Cube& cube) {
  std::set<std::array<int, 3>> v;
  std::set<std::array<int, 4>> e, f;
  long cubes = 0;
  for (int c = 0; c < 27; ++c) {
    if (!cube[size_t(c)]) continue;
    ++cubes;
    const int x = 2 * (c % 3), y = 2 * (c / 3 % 3), z = 2 * (c / 9);
    // Cells by their doubled-coordinate centres: a cell's centre names it uniquely.
    for (int dx = 0; dx <= 2; ++dx)
      for (int dy = 0; dy <= 2; ++dy)
        for (int dz = 0; dz <= 2; ++dz) {
          const int odd = (dx == 1) + (dy == 1) + (dz == 1);
          const std::array<int, 3> p{x + dx, y + dy, z + dz};
          if (odd == 0) v.insert(p);
          if (odd == 1) e.insert({p[0], p[1], p[2], 0});
          if (odd == 2) f.insert({p[0], p[1], p[2], 0});
        }
  }
  return long(v.size()) - long(e.size()) + long(f.size()) - cubes;
}

TEST(Envelope, SimplePointTestAgreesWithAnIndependentCount) {
  std::mt19937 random(29);
  std::vector<int> n26, n18;
  for (int c = 0; c < 27; ++c) {
    if (c == 13) continue;
    n26.push_back(c);
    const int odd = (c % 3 != 1) + (c / 3 % 3 != 1) + (c / 9 != 1);
    if (odd <= 2) n18.push_back(c);
  }
  int simple = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Cube cube{};
    const double density = (trial % 9 + 1) / 10.0;
    uint32_t bits = 0;
    for (int c = 0; c < 27; ++c) {
      cube[size_t(c)] = c != 13 && std::uniform_real_distribution<>(0, 1)(random) < density;
      bits |= uint32_t(cube[size_t(c)]) << c;
    }
    const bool expected =
        components(cube, 1, n26, false, false) == 1 && components(cube, 0, n18, true, true) == 1;
    ASSERT_EQ(is_simple_point(bits), expected) << "neighbourhood " << bits;
    if (expected) {
      ++simple;
      // A simple point does not change the Euler characteristic.
      Cube with = cube;
      with[13] = 1;
      EXPECT_EQ(euler_characteristic(with), euler_characteristic(cube)) << bits;
    }
  }
  EXPECT_GT(simple, 1000);                                // the trials reach both answers
  EXPECT_FALSE(is_simple_point(0));                       // an isolated voxel
  EXPECT_TRUE(is_simple_point(1u << 4));                  // one face neighbour
  EXPECT_FALSE(is_simple_point((1u << 4) | (1u << 22)));  // would join two
  EXPECT_TRUE(stays_well_composed(1u << 4));              // face contact
  EXPECT_FALSE(stays_well_composed(1u << 0));             // corner contact
  EXPECT_FALSE(stays_well_composed(1u << 1));             // edge contact
}

// --- steps_to_other against a breadth-first search -------------------------------------

// The definition: 6-steps through voxels of `from` from those next to the other kind
// (border voxels of the grid not started from), 0 where none is reached.
std::vector<uint16_t> steps_by_definition(const VoxelGrid& g, const std::vector<uint8_t>& inside,
                                          uint8_t from) {
  std::vector<uint16_t> steps(g.size(), 0);
  std::vector<std::array<int, 3>> front, next;
  const auto at = [&](int x, int y, int z) { return g.index(x, y, z); };
  const auto inner = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < g.nx && y < g.ny && z < g.nz;
  };
  const std::array<std::array<int, 3>, 6> moves{
      {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};
  for (int z = 1; z + 1 < g.nz; ++z)
    for (int y = 1; y + 1 < g.ny; ++y)
      for (int x = 1; x + 1 < g.nx; ++x) {
        if (inside[at(x, y, z)] != from) continue;
        for (const auto& m : moves)
          if (inside[at(x + m[0], y + m[1], z + m[2])] != from) {
            steps[at(x, y, z)] = 1, front.push_back({x, y, z});
            break;
          }
      }
  for (uint16_t level = 2; !front.empty(); ++level) {
    next.clear();
    for (const auto& c : front)
      for (const auto& m : moves) {
        const int x = c[0] + m[0], y = c[1] + m[1], z = c[2] + m[2];
        if (!inner(x, y, z) || inside[at(x, y, z)] != from || steps[at(x, y, z)]) continue;
        steps[at(x, y, z)] = level, next.push_back({x, y, z});
      }
    front.swap(next);
  }
  return steps;
}

TEST(Envelope, StepsToOtherAgreeWithASearch) {
  std::mt19937 random(34);
  int compared = 0;
  for (int trial = 0; trial < 60; ++trial) {
    VoxelGrid g;
    g.h = 1;
    g.nx = 3 + int(random() % 14), g.ny = 3 + int(random() % 14), g.nz = 3 + int(random() % 14);
    std::vector<uint8_t> inside(g.size(), 0);
    // Random boxes and single voxels; every third grid keeps them off a 2-voxel border
    // (as the envelope's padding does), the others let them touch it.
    const int margin = trial % 3 == 0 ? 2 : 0;
    if (g.nx <= 2 * margin + 1 || g.ny <= 2 * margin + 1 || g.nz <= 2 * margin + 1) continue;
    const auto pick = [&](int n) { return margin + int(random() % unsigned(n - 2 * margin)); };
    for (int box = 0; box < int(random() % 5); ++box) {
      const int x0 = pick(g.nx), y0 = pick(g.ny), z0 = pick(g.nz);
      const int x1 = std::max(x0, pick(g.nx)), y1 = std::max(y0, pick(g.ny)),
                z1 = std::max(z0, pick(g.nz));
      for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) inside[g.index(x, y, z)] = 1;
    }
    for (int k = 0; k < int(random() % 40); ++k)
      inside[g.index(pick(g.nx), pick(g.ny), pick(g.nz))] ^= 1;
    StopCheck stop(nullptr);
    for (const uint8_t from : {uint8_t{0}, uint8_t{1}}) {
      ASSERT_EQ(steps_to_other(g, inside, from, stop), steps_by_definition(g, inside, from))
          << "trial " << trial << " from " << int(from);
      ++compared;
    }
  }
  EXPECT_GT(compared, 80);
  // A grid of one kind only: nothing to step to.
  VoxelGrid g;
  g.h = 1, g.nx = g.ny = g.nz = 5;
  StopCheck stop(nullptr);
  EXPECT_EQ(steps_to_other(g, std::vector<uint8_t>(g.size(), 0), 0, stop),
            std::vector<uint16_t>(g.size(), 0));
}

// The definition of fill_enclosed: 1 unless a 6-connected walk through 0 voxels leads
// from the voxel to the grid's border.
std::vector<uint8_t> filled_by_definition(const VoxelGrid& g, const std::vector<uint8_t>& band) {
  std::vector<uint8_t> outside(g.size(), 0);
  std::vector<std::array<int, 3>> stack;
  const auto visit = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= g.nx || y >= g.ny || z >= g.nz) return;
    const size_t i = g.index(x, y, z);
    if (!band[i] && !outside[i]) outside[i] = 1, stack.push_back({x, y, z});
  };
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x)
        if (x == 0 || y == 0 || z == 0 || x == g.nx - 1 || y == g.ny - 1 || z == g.nz - 1)
          visit(x, y, z);
  while (!stack.empty()) {
    const auto [x, y, z] = stack.back();
    stack.pop_back();
    visit(x - 1, y, z), visit(x + 1, y, z), visit(x, y - 1, z), visit(x, y + 1, z);
    visit(x, y, z - 1), visit(x, y, z + 1);
  }
  std::vector<uint8_t> solid(g.size());
  for (size_t i = 0; i < solid.size(); ++i) solid[i] = !outside[i];
  return solid;
}

TEST(Envelope, FillEnclosedAgreesWithAVoxelByVoxelFill) {
  std::mt19937 random(341);
  size_t enclosed = 0;
  for (int trial = 0; trial < 80; ++trial) {
    VoxelGrid g;
    g.h = 1;
    g.nx = 1 + int(random() % 16), g.ny = 1 + int(random() % 16), g.nz = 1 + int(random() % 16);
    std::vector<uint8_t> band(g.size(), 0);
    // Hollow boxes (some with a hole in a wall), plus random voxels at various densities.
    for (int box = 0; box < int(random() % 4); ++box) {
      const int x0 = int(random() % unsigned(g.nx)), y0 = int(random() % unsigned(g.ny)),
                z0 = int(random() % unsigned(g.nz));
      const int x1 = std::min(g.nx - 1, x0 + 2 + int(random() % 8)),
                y1 = std::min(g.ny - 1, y0 + 2 + int(random() % 8)),
                z1 = std::min(g.nz - 1, z0 + 2 + int(random() % 8));
      for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x)
            if (x == x0 || x == x1 || y == y0 || y == y1 || z == z0 || z == z1)
              band[g.index(x, y, z)] = 1;
      if (random() % 3 == 0) band[g.index(x0, (y0 + y1) / 2, (z0 + z1) / 2)] = 0;
    }
    const double density = (trial % 5) / 10.0;
    for (uint8_t& v : band)
      if (std::uniform_real_distribution<>(0, 1)(random) < density) v = 1;
    const std::vector<uint8_t> expected = filled_by_definition(g, band);
    std::vector<uint8_t> solid = band;
    StopCheck stop(nullptr);
    fill_enclosed(g, solid, stop);
    ASSERT_EQ(solid, expected) << "trial " << trial;
    for (size_t i = 0; i < band.size(); ++i) enclosed += solid[i] && !band[i];
  }
  EXPECT_GT(enclosed, 100u);  // the trials enclose voxels
}

// --- band_voxels against every voxel and every triangle ---------------------------------

TEST(Envelope, TheBandIsEveryVoxelWithinTheOffset) {
  std::mt19937 random(3434);
  size_t marked = 0;
  for (int trial = 0; trial < 24; ++trial) {
    // Small triangles, slivers and needles (the skip of far centres assumes the computed
    // closest point stays in the triangle's box), near the origin and far from it.
    const double shift = trial % 3 == 0 ? 0.0 : (trial % 3 == 1 ? 1e4 : -3e6);
    std::uniform_real_distribution<> unit(0, 1);
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    for (int t = 0; t < 12; ++t) {
      const Vec3 a{shift + 4 * unit(random), shift + 4 * unit(random), 4 * unit(random)};
      const double size = t % 2 ? 0.05 : 1.5;
      Vec3 b = a + Vec3{size * unit(random), size * unit(random), size * unit(random)};
      Vec3 c = a + Vec3{size * unit(random), size * unit(random), size * unit(random)};
      if (t % 4 == 1) c = a + (b - a) * 0.5 + Vec3{0, 1e-9 * unit(random), 0};  // a sliver
      if (t % 4 == 3) c = b + Vec3{1e-12, 0, 0};                                // a needle
      const uint32_t first = uint32_t(positions.size());
      positions.insert(positions.end(), {a, b, c});
      triangles.push_back({first, first + 1, first + 2});
    }
    const double h = 0.1 + 0.1 * unit(random), d = 1.5 * h;
    VoxelGrid g = layout_grid(Vec3{shift, shift, 0}, Vec3{shift + 6, shift + 6, 6}, h, d, 1u << 22);
    StopCheck stop(nullptr);
    const std::vector<uint8_t> band = band_voxels(g, positions, triangles, d, stop);
    for (int z = 0; z < g.nz; ++z)
      for (int y = 0; y < g.ny; ++y)
        for (int x = 0; x < g.nx; ++x) {
          const Vec3 p = g.center(x, y, z);
          bool within = false;
          for (const Triangle& t : triangles)
            within |= squared_norm(closest_on_triangle(p, positions[t[0]], positions[t[1]],
                                                       positions[t[2]]) -
                                   p) <= d * d;
          ASSERT_EQ(band[g.index(x, y, z)], uint8_t(within))
              << "trial " << trial << " voxel " << x << " " << y << " " << z;
          marked += within;
        }
  }
  EXPECT_GT(marked, 1000u);
}

// --- envelopes of meshes that do not map ---------------------------------------------

struct Checked {
  Envelope envelope;
  TopologyReport topology;
};

Checked wrapped(const PolygonMesh& input, double resolution = 96) {
  EnvelopeOptions options;
  options.resolution = resolution;
  Checked out{build_envelope(input, options), {}};
  out.topology = analyze_topology(weld(out.envelope.mesh).mesh);
  return out;
}

void expect_sphere_like(const Checked& c, const char* name) {
  EXPECT_EQ(envelope_failures(c.envelope.mesh), "") << name;
  EXPECT_TRUE(c.topology.closed()) << name;
  EXPECT_TRUE(c.topology.manifold()) << name;
  EXPECT_EQ(c.topology.component_vertices.size(), 1u) << name;
  EXPECT_EQ(c.topology.genus(), 0) << name;
  EXPECT_GT(c.topology.signed_volume, 0) << name;  // facing out
  const EnvelopeReport& r = c.envelope.report;
  EXPECT_GT(r.faces, 0u) << name;
  EXPECT_LE(r.faces, r.voxel_faces) << name;
  std::printf(
      "%s: rule %s, cut %zu, filled %zu, changed %zu, voxel faces %zu, faces %zu, "
      "hausdorff %.4f (envelope->original %.4f, original->envelope %.4f), rms %.4f, "
      "offset %.4f\n",
      name, r.rule.c_str(), r.handles_cut, r.handles_filled, r.voxels_changed, r.voxel_faces,
      r.faces, r.hausdorff, r.envelope_to_original, r.original_to_envelope, r.rms,
      r.offset / r.diagonal);
  EXPECT_GT(r.hausdorff, 0) << name;
  EXPECT_LT(r.rms, r.hausdorff + 1e-12) << name;
  EXPECT_NEAR(r.hausdorff, std::max(r.envelope_to_original, r.original_to_envelope), 1e-12);
  // Where nothing was cut or filled the envelope is within a few voxels of the original.
  if (r.voxels_changed == 0) {
    EXPECT_LT(r.envelope_to_original, 4.0 / 96) << name;
  }
}

PolygonMesh box(const Vec3& lo, const Vec3& hi) {
  PolygonMesh m = testing::quad_cube(2);
  for (Vec3& p : m.positions) {
    // quad_cube spans [-1, 1]^3.
    p = {lo.x + (p.x + 1) / 2 * (hi.x - lo.x), lo.y + (p.y + 1) / 2 * (hi.y - lo.y),
         lo.z + (p.z + 1) / 2 * (hi.z - lo.z)};
  }
  return m;
}

// Every triangle with corners of its own, in a random order: no two faces share a vertex.
PolygonMesh soup(const PolygonMesh& mesh) {
  const FanTriangulation fan = fan_triangulate(mesh);
  std::vector<Triangle> order = fan.triangles;
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  PolygonMesh out;
  for (const Triangle& t : order) {
    const uint32_t first = uint32_t(out.positions.size());
    for (uint32_t v : t) out.positions.push_back(mesh.positions[v]);
    const std::array<uint32_t, 3> corners{first, first + 1, first + 2};
    out.add_face(corners);
  }
  return out;
}

PolygonMesh plane(int n) {
  PolygonMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.push_back({double(i) / n, double(j) / n, 0.1 * std::sin(3.0 * i / n)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i);
      const std::array<uint32_t, 4> q{a, a + 1, a + uint32_t(n) + 2, a + uint32_t(n) + 1};
      m.add_face(q);
    }
  return m;
}

// Two faces over four nearly collinear points (pytorch3d's missing_files_obj/model.obj):
// the faces' normals are rounding noise, and the band once followed them, so the envelope
// held a third of the segment (a third of the diagonal off). It must hold all of it.
TEST(Envelope, OfNearlyCollinearFacesHoldsTheWholeSegment) {
  PolygonMesh line;
  line.positions = {{0.1, 0.2, 0.3}, {0.2, 0.3, 0.4}, {0.3, 0.4, 0.5}, {0.4, 0.5, 0.6}};
  for (const Triangle& t : {Triangle{0, 1, 2}, Triangle{0, 1, 3}}) line.add_face(t);
  const Checked c = wrapped(line);
  expect_sphere_like(c, "nearly collinear faces");
  EXPECT_LT(c.envelope.report.original_to_envelope, 4.0 / 96);
  EXPECT_LT(c.envelope.report.hausdorff, 4.0 / 96);
}

TEST(Envelope, ATorusBecomesAClosedGenusZeroEnvelope) {
  const Checked c = wrapped(testing::torus(48, 96));
  expect_sphere_like(c, "torus");
  const EnvelopeReport& r = c.envelope.report;
  EXPECT_EQ(r.handles_cut + r.handles_filled, 1u);  // the one handle, cut or filled
  EXPECT_GT(r.voxels_changed, 0u);
  EXPECT_GT(r.solid_voxels, r.voxels_changed);
  EXPECT_EQ(r.rule, r.handles_cut ? "cut" : "fill");
}

TEST(Envelope, AnythingBecomesOneClosedGenusZeroEnvelope) {
  const PolygonMesh sphere = testing::icosphere(3);
  expect_sphere_like(wrapped(soup(sphere)), "soup");
  expect_sphere_like(
      wrapped(testing::assembled({{box({0, 0, 0}, {2, 1, 1}), {0, 0, 0}},
                                  {box({0.5, -0.5, 0.2}, {1.2, 1.5, 0.8}), {0, 0, 0}}})),
      "two intersecting boxes");
  expect_sphere_like(wrapped(plane(20)), "open plane");
  expect_sphere_like(wrapped(testing::dome(3)), "dome");
  // A thick ring: a sphere with a through-hole.
  PolygonMesh ring = testing::torus(32, 64);
  for (Vec3& p : ring.positions) p.z *= 1.5;
  expect_sphere_like(wrapped(ring), "sphere with a through-hole");
  // Disjoint parts: one envelope holds them all (the outside grown inward joins them).
  const Checked parts = wrapped(testing::assembled(
      {{sphere, {0, 0, 0}}, {sphere, {2.6, 0, 0}}, {testing::torus(16, 32), {0, 4.5, 0}}}));
  expect_sphere_like(parts, "three disjoint parts");
  EXPECT_NE(parts.envelope.report.rule, "cut");  // cutting would drop two of the parts
}

// A ring of major radius `major` and tube radius `tube` in the xy plane around `centre`.
PolygonMesh ring(double major, double tube, const Vec3& centre) {
  PolygonMesh m = testing::torus(24, 48);  // major 2, tube 1
  for (Vec3& p : m.positions) {
    const double rho = std::hypot(p.x, p.y), scale = (major + (rho - 2) * tube) / rho;
    p = {centre.x + p.x * scale, centre.y + p.y * scale, centre.z + p.z * tube};
  }
  return m;
}

// Two handles, one cheap to cut (a thin ring: a small cross-section, a wide hole) and one
// cheap to fill (a fat ring: a small hole, a wide cross-section), in one solid: the mixed
// rule cuts the one and fills the other, fewer voxels than either rule alone, and its
// region is still a ball (its voxel surface a closed genus-0 surface).
TEST(Envelope, EachHandleGetsItsSmallerChange) {
  const PolygonMesh input = testing::assembled(
      {{ring(2, 0.25, {0, 0, 0}), {0, 0, 0}}, {ring(1.5, 1, {3.6, 0, 0}), {0, 0, 0}}});
  EnvelopeOptions options;
  options.resolution = 96;
  const Checked c = wrapped(input, options.resolution);
  expect_sphere_like(c, "thin and fat rings");
  const EnvelopeReport& r = c.envelope.report;
  EXPECT_EQ(r.rule, "mixed");
  EXPECT_GE(r.handles_cut, 1u);
  EXPECT_GE(r.handles_filled, 1u);
  // The three rules side by side on the same solid.
  const FanTriangulation fan = fan_triangulate(input);
  const double h = r.voxel_size;
  Vec3 lo = input.positions[0], hi = lo;
  for (const Vec3& p : input.positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const VoxelGrid grid = layout_grid(lo, hi, h, r.offset, options.max_voxels);
  StopCheck stop(nullptr);
  const std::vector<uint8_t> solid =
      solid_voxels(grid, input.positions, fan.triangles, r.offset, stop);
  const BallGrowth cut = grow_ball_inside(grid, solid, stop);
  const BallGrowth fill = shrink_ball_outside(grid, solid, stop);
  size_t kept = 0;
  const BallGrowth mixed = grow_ball_mixed(grid, solid, cut, fill, &kept, stop);
  std::printf("changed voxels: cut %zu (%zu groups), fill %zu (%zu), mixed %zu (%zu, %zu fills)\n",
              cut.voxels_changed, cut.changes, fill.voxels_changed, fill.changes,
              mixed.voxels_changed, mixed.changes, kept);
  EXPECT_LT(mixed.voxels_changed, std::min(cut.voxels_changed, fill.voxels_changed));
  EXPECT_EQ(mixed.voxels_changed, r.voxels_changed);
  EXPECT_GE(kept, 1u);
}

TEST(Envelope, ASpheresEnvelopeLiesAtTheFitDistance) {
  const PolygonMesh sphere = testing::icosphere(4);
  const Checked c = wrapped(sphere, 128);
  expect_sphere_like(c, "sphere");
  const EnvelopeReport& r = c.envelope.report;
  EXPECT_EQ(r.voxels_changed, 0u);
  EXPECT_EQ(r.handles_cut + r.handles_filled, 0u);
  const double d = r.offset / r.diagonal;
  EXPECT_NEAR(r.offset, 1.5 * r.voxel_size, 1e-12);
  // The solid reaches the offset; the surface is fitted back to fit_distance.
  const double fit = r.fit_distance / r.diagonal;
  EXPECT_LT(r.fit_distance, r.offset);
  EXPECT_GT(r.hausdorff, 0.5 * fit);
  EXPECT_LT(r.hausdorff, 2.0 * d);
  // Every envelope vertex is about fit_distance from the unit sphere.
  for (const Vec3& p : c.envelope.mesh.positions)
    EXPECT_NEAR(norm(p) - 1, r.fit_distance, r.fit_distance);
}

// The fit's closest-point queries run in parallel, before each round's moves: the
// envelope must not depend on how many threads made them.
TEST(Envelope, TheEnvelopeDoesNotDependOnTheThreadCount) {
  EnvelopeOptions one, two;
  one.threads = 1, two.threads = 2;
  const PolygonMesh input = testing::torus(48, 96);
  const Envelope a = build_envelope(input, one), b = build_envelope(input, two);
  ASSERT_GT(a.mesh.vertex_count(), 8192u);  // past the parallel loops' serial threshold
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.report.hausdorff, b.report.hausdorff);
  EXPECT_EQ(a.report.rms, b.report.rms);
}

TEST(Envelope, OffsetAndTargetOptionsAreFollowed) {
  EnvelopeOptions options;
  options.resolution = 64;
  options.offset_fraction = 0.05;
  options.target_faces = 1500;
  const Envelope e = build_envelope(testing::torus(24, 48), options);
  EXPECT_NEAR(e.report.offset, 0.05 * e.report.diagonal, 1e-12);
  EXPECT_LE(e.report.faces, 1500u);  // the reduction reaches its target
  EXPECT_EQ(envelope_failures(e.mesh), "");
}

// A caller that measures the envelope against other faces (a repaired part's own input
// faces) asks for no distances: the same envelope, its report's distances left 0.
TEST(Envelope, WithoutItsDistanceTheEnvelopeIsTheSame) {
  EnvelopeOptions measured;
  measured.resolution = 64;
  EnvelopeOptions unmeasured = measured;
  unmeasured.measure_distance = false;
  const PolygonMesh input = testing::torus(24, 48);
  const Envelope a = build_envelope(input, measured), b = build_envelope(input, unmeasured);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.mesh.indices, b.mesh.indices);
  EXPECT_GT(a.report.hausdorff, 0);
  EXPECT_GT(a.report.rms, 0);
  EXPECT_EQ(b.report.hausdorff, 0);
  EXPECT_EQ(b.report.rms, 0);
  EXPECT_EQ(b.report.envelope_to_original + b.report.original_to_envelope, 0);
}

TEST(Envelope, HostileSizesAreRefusedBeforeAllocating) {
  EnvelopeOptions options;
  options.resolution = 1e6;
  try {
    build_envelope(testing::icosphere(1), options);
    FAIL() << "a grid of about 1e17 voxels was not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "envelope_size");
    EXPECT_NE(std::string(e.what()).find("cap"), std::string::npos) << e.what();
  }
  PolygonMesh flat;  // no extent
  flat.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  flat.add_face(std::array<uint32_t, 3>{0, 1, 2});
  EXPECT_THROW(build_envelope(flat, {}), InputError);
  EXPECT_THROW(build_envelope(PolygonMesh{}, {}), InputError);
}

TEST(Envelope, TheStopCallbackIsHonoured) {
  int asked = 0;
  const std::function<bool()> stop = [&] { return ++asked > 3; };
  try {
    build_envelope(testing::torus(48, 96), {}, &stop);
    FAIL() << "not stopped";
  } catch (const InputError& e) {
    EXPECT_EQ(e.check(), "stopped");
  }
  EXPECT_EQ(asked, 4);
}

TEST(Envelope, AWrappedTorusMapsCertified) {
  PolygonMesh input = testing::torus(32, 64);
  const size_t input_faces = input.face_count();
  PrepareOptions options;
  options.method = PrepareMethod::kWrap;
  options.envelope.resolution = 96;
  options.envelope.target_faces = 3000;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  EXPECT_EQ(prepared.preparation.method, PrepareMethod::kWrap);
  EXPECT_EQ(prepared.preparation.input_faces, input_faces);
  EXPECT_EQ(
      prepared.preparation.envelope.handles_cut + prepared.preparation.envelope.handles_filled, 1u);
  EXPECT_EQ(input.face_count(), prepared.welded.mesh.face_count());  // the input is the envelope
  ASSERT_TRUE(remaining_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

// --- fidelity: the surface is fitted close to the original ---------------------------

// A tube of radius 0.3 and length 1 along z, open at both ends (quads, `around` x `along`).
PolygonMesh open_cylinder(int around, int along) {
  PolygonMesh m;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const double a = 2 * std::numbers::pi * i / around;
      m.positions.push_back({0.3 * std::cos(a), 0.3 * std::sin(a), double(j) / along});
    }
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const auto at = [&](int jj, int ii) { return uint32_t(jj * around + (ii % around)); };
      const std::array<uint32_t, 4> q{at(j, i), at(j, i + 1), at(j + 1, i + 1), at(j + 1, i)};
      m.add_face(q);
    }
  return m;
}

// Where no handle was filled, the envelope's vertices lie about fit_distance (half a voxel
// by default, not the offset's 1.5) from the original, and no envelope point is a voxel
// away: the offset makes the solid, the fit brings the surface back. (Not yet at concave
// creases: two intersecting boxes' envelope stays about 2 voxels off where they meet. And a
// bound measured here, not guaranteed: a vertex whose move would fold stays where the
// smoothing left it; the wavy plane's rim at 96 voxels stays 1.8 voxels off.) With the old
// fit distance (fit_voxels = 1.5) all three fail: 1.50, 1.52 and 1.58 voxels. Before the
// fit went to the original's closest point, every one of these was at 1.5 voxels or more.
TEST(Envelope, TheSurfaceIsFittedWithinAVoxelOfTheOriginal) {
  const Checked sphere = wrapped(testing::icosphere(4), 128);
  expect_sphere_like(sphere, "sphere");
  const EnvelopeReport& s = sphere.envelope.report;
  EXPECT_NEAR(s.fit_distance, 0.5 * s.voxel_size, 1e-12);
  for (const Vec3& p : sphere.envelope.mesh.positions)
    EXPECT_NEAR(norm(p) - 1, s.fit_distance, 0.25 * s.voxel_size);
  const std::vector<std::pair<const char*, PolygonMesh>> inputs = {
      {"sphere", testing::icosphere(4)},
      {"open plane", plane(20)},
      {"open cylinder", open_cylinder(48, 16)},
  };
  for (const auto& [name, input] : inputs) {
    const Checked c = wrapped(input, 128);
    expect_sphere_like(c, name);
    const EnvelopeReport& r = c.envelope.report;
    // A cut only takes material away (the open cylinder's ring is cut); a fill adds some.
    // The mixed rule keeps only fills smaller than the cuts they touch (the open cylinder at
    // 128: 4 small fills beside 38 cut groups, 1,266 voxels, and still within a voxel).
    ASSERT_TRUE(r.rule != "fill" || r.voxels_changed == 0) << name;
    const double voxel = r.voxel_size / r.diagonal;
    EXPECT_LT(r.envelope_to_original, 1.0 * voxel) << name;
  }
}

// A user's larger offset still makes the solid, and the fit still comes back to half a
// voxel; a smaller offset than that is kept as the fit distance.
TEST(Envelope, TheFitDistanceIsTheSmallerOfOffsetAndFitVoxels) {
  EnvelopeOptions options;
  options.resolution = 64;
  options.offset_voxels = 4;
  const Envelope wide = build_envelope(open_cylinder(32, 8), options);
  EXPECT_NEAR(wide.report.fit_distance, 0.5 * wide.report.voxel_size, 1e-12);
  EXPECT_EQ(envelope_failures(wide.mesh), "");
  options.offset_voxels = 1.5;
  options.fit_voxels = 2;
  const Envelope narrow = build_envelope(open_cylinder(32, 8), options);
  EXPECT_NEAR(narrow.report.fit_distance, narrow.report.offset, 1e-12);
  EXPECT_EQ(envelope_failures(narrow.mesh), "");
}

// The open cylinder, wrapped and fitted close, still maps certified.
TEST(Envelope, AWrappedOpenCylinderMapsCertified) {
  PolygonMesh input = open_cylinder(48, 16);
  PrepareOptions options;
  options.method = PrepareMethod::kWrap;
  options.envelope.resolution = 128;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  ASSERT_TRUE(remaining_failures(prepared).empty());
  const EnvelopeReport& r = prepared.preparation.envelope;
  EXPECT_LT(r.envelope_to_original, r.voxel_size / r.diagonal);
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

}  // namespace
}  // namespace spheremap
