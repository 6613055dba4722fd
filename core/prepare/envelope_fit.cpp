#include "core/prepare/envelope_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace spheremap {
namespace {

std::vector<Triangle> triangles_of(const PolygonMesh& mesh) {
  std::vector<Triangle> out(mesh.face_count());
  for (size_t f = 0; f < out.size(); ++f) {
    const auto c = mesh.face(f);
    out[f] = {c[0], c[1], c[2]};
  }
  return out;
}

// Whether moving vertex v to p keeps every incident triangle within 60 degrees of its
// normal now and of a non-negligible area.
bool move_keeps_shape(const PolygonMesh& mesh, const std::vector<Triangle>& triangles,
                      const VertexTriangles& around, uint32_t v, const Vec3& p) {
  for (const uint32_t t : around.of(v)) {
    const Triangle& tri = triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]],
               &c = mesh.positions[tri[2]];
    const Vec3 before = cross(b - a, c - a);
    const Vec3 a2 = tri[0] == v ? p : a, b2 = tri[1] == v ? p : b, c2 = tri[2] == v ? p : c;
    const Vec3 after = cross(b2 - a2, c2 - a2);
    const double nb = norm(before), na = norm(after);
    const double longest =
        std::max({squared_norm(b2 - a2), squared_norm(c2 - b2), squared_norm(a2 - c2)});
    if (!(na > 1e-6 * longest) || !(dot(before, after) > 0.5 * nb * na)) return false;
  }
  return true;
}

// The mean of v's neighbours (each appears in two incident triangles of a closed manifold).
Vec3 neighbour_mean(const PolygonMesh& mesh, const std::vector<Triangle>& triangles,
                    const VertexTriangles& around, uint32_t v) {
  Vec3 sum;
  size_t count = 0;
  for (const uint32_t t : around.of(v))
    for (const uint32_t w : triangles[t])
      if (w != v) sum += mesh.positions[w], ++count;
  return count ? sum * (1.0 / double(count)) : mesh.positions[v];
}

void laplacian_step(PolygonMesh& mesh, const std::vector<Triangle>& triangles,
                    const VertexTriangles& around, double factor, StopCheck& stop) {
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    stop.tick();
    const Vec3 p = mesh.positions[v];
    const Vec3 target = p + (neighbour_mean(mesh, triangles, around, v) - p) * factor;
    if (move_keeps_shape(mesh, triangles, around, v, target)) mesh.positions[v] = target;
  }
}

}  // namespace

void smooth_surface(PolygonMesh& mesh, int iterations, StopCheck& stop) {
  const std::vector<Triangle> triangles = triangles_of(mesh);
  const VertexTriangles around = vertex_triangles(triangles, mesh.vertex_count());
  for (int k = 0; k < iterations; ++k) {
    laplacian_step(mesh, triangles, around, 0.5, stop);
    laplacian_step(mesh, triangles, around, -0.53, stop);
  }
}

size_t fit_to_offset(PolygonMesh& mesh, const TriangleTree& original, double offset, int iterations,
                     StopCheck& stop) {
  const std::vector<Triangle> triangles = triangles_of(mesh);
  const VertexTriangles around = vertex_triangles(triangles, mesh.vertex_count());
  size_t moved = 0;
  for (int k = 0; k < iterations; ++k) {
    moved = 0;
    for (uint32_t v = 0; v < mesh.vertex_count(); ++v) {
      stop.tick();
      const Vec3 p = mesh.positions[v];
      const TriangleTree::Closest q = original.closest(p);
      const double distance = std::sqrt(q.squared_distance);
      if (!(distance > 0)) continue;
      const Vec3 target = q.point + (p - q.point) * (offset / distance);
      if (move_keeps_shape(mesh, triangles, around, v, target)) mesh.positions[v] = target, ++moved;
    }
    if (k + 1 < iterations) laplacian_step(mesh, triangles, around, 0.5, stop);
  }
  return moved;
}

}  // namespace spheremap
