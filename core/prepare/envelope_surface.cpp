#include "core/prepare/envelope_surface.h"

#include <algorithm>
#include <array>

namespace spheremap {

PolygonMesh voxel_surface(const VoxelGrid& g, const std::vector<uint8_t>& ball, StopCheck& stop) {
  const uint64_t cx = uint64_t(g.nx) + 1, cy = uint64_t(g.ny) + 1;
  const auto key = [&](int x, int y, int z) {
    return (uint64_t(z) * cy + uint64_t(y)) * cx + uint64_t(x);
  };
  // Per boundary face its 4 corners, counter-clockwise seen from outside.
  std::vector<std::array<uint64_t, 4>> quads;
  // Per axis: the unit step along it and the two in-plane steps (u, v) with u x v = +axis.
  constexpr std::array<std::array<std::array<int, 3>, 3>, 3> frame{{
      {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {{{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}},
      {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}},
  }};
  for (int z = 1; z + 1 < g.nz; ++z)
    for (int y = 1; y + 1 < g.ny; ++y)
      for (int x = 1; x + 1 < g.nx; ++x) {
        stop.tick();
        if (!ball[g.index(x, y, z)]) continue;
        for (int axis = 0; axis < 3; ++axis)
          for (const int side : {-1, 1}) {
            const auto& [n, u, v] = frame[size_t(axis)];
            if (ball[g.index(x + side * n[0], y + side * n[1], z + side * n[2])]) continue;
            // The face's plane: the voxel's low corner plus n when on the high side.
            const int px = x + (side > 0) * n[0], py = y + (side > 0) * n[1],
                      pz = z + (side > 0) * n[2];
            std::array<uint64_t, 4> q{key(px, py, pz), key(px + u[0], py + u[1], pz + u[2]),
                                      key(px + u[0] + v[0], py + u[1] + v[1], pz + u[2] + v[2]),
                                      key(px + v[0], py + v[1], pz + v[2])};
            if (side < 0) std::swap(q[1], q[3]);
            quads.push_back(q);
          }
      }
  std::vector<uint64_t> corners;
  corners.reserve(quads.size() * 4);
  for (const auto& q : quads) corners.insert(corners.end(), q.begin(), q.end());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  PolygonMesh mesh;
  mesh.positions.reserve(corners.size());
  for (const uint64_t k : corners) {
    const double x = double(k % cx), y = double(k / cx % cy), z = double(k / (cx * cy));
    mesh.positions.push_back(g.origin + Vec3{x * g.h, y * g.h, z * g.h});
  }
  mesh.offsets.reserve(2 * quads.size() + 1);
  mesh.indices.reserve(6 * quads.size());
  const auto id = [&](uint64_t k) {
    return uint32_t(std::lower_bound(corners.begin(), corners.end(), k) - corners.begin());
  };
  for (const auto& q : quads) {
    const std::array<uint32_t, 4> c{id(q[0]), id(q[1]), id(q[2]), id(q[3])};
    const std::array<uint32_t, 3> t0{c[0], c[1], c[2]}, t1{c[0], c[2], c[3]};
    mesh.add_face(t0);
    mesh.add_face(t1);
  }
  return mesh;
}

}  // namespace spheremap
