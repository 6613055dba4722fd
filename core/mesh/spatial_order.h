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
std::vector<uint32_t> morton_order(std::span<const Vec3> positions);

// The mesh with vertices renumbered by order (faces unchanged but for the ids).
PolygonMesh reordered(const PolygonMesh& mesh, const std::vector<uint32_t>& order);

// The triangles in an order that depends on their vertex ids only, not on the order they
// came in: each rotated to start at its smallest corner (orientation kept), sorted by
// (first, second, third). Two reasons. With vertices in Morton order, a pass over the
// triangles reads the positions in order too (in a scanned file's order they jump
// across memory). And the map then no longer depends on the file's face order: sums over
// triangles (quadrics, energies) and the hierarchy's tie-breaks took it from there, so the
// same mesh saved by two exporters could map differently (on CAD shapes, where costs
// tie exactly, visibly so). Precondition: every id is below `vertices`.
std::vector<Triangle> canonical_triangles(std::span<const Triangle> triangles, size_t vertices);

}  // namespace spheremap
