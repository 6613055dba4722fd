// A cache-friendly vertex order: vertices sorted along a Morton (Z-order) curve of their
// positions, so neighbours on the surface are mostly neighbours in memory. Scanned and
// subdivided meshes store vertices in arbitrary order; every pass of the mapper walks
// rings, so their order decides its cache misses.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

// order[new id] = old id.
std::vector<uint32_t> morton_order(const std::vector<Vec3>& positions);

// The mesh with vertices renumbered by order (faces unchanged but for the ids).
PolygonMesh reordered(const PolygonMesh& mesh, const std::vector<uint32_t>& order);

// The triangles ordered by their smallest vertex id (stable; each keeps its corners).
// With vertices in Morton order, a pass over the triangles then reads the positions in
// order too; in the file's order a scanned mesh's triangles jump across memory.
std::vector<Triangle> sorted_by_vertex(std::span<const Triangle> triangles, size_t vertices);

}  // namespace spheremap
