// A mesh made of some faces of another mesh: the faces in the order given, their vertices
// renumbered in first-use order, and each new vertex's index in the whole mesh.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/weld.h"  // kUnreferenced

namespace spheremap {

struct MeshPart {
  PolygonMesh mesh;              // the faces, their vertices in first-use order
  std::vector<uint32_t> vertex;  // per vertex of `mesh`: its index in the whole mesh
};

// Inputs: `mesh`; `faces`, face indices of `mesh` (< face_count; repeats allowed, each
// becomes a face). `scratch` (may be null): mesh.vertex_count() entries, all kUnreferenced
// on entry, and left so on return, so that many calls on one mesh cost O(their corners)
// rather than O(vertices) each.
// Output: the faces as a mesh of their own, with the map new vertex -> old vertex. Vertices
// no face names are dropped. O(corners) (+ O(vertices) without scratch).
MeshPart submesh(const PolygonMesh& mesh, std::span<const uint32_t> faces,
                 std::vector<uint32_t>* scratch = nullptr);

// The triangles whose `left_out` entry (one per triangle, e.g. filled_mask's marks of the
// faces a repair added) is 0, in their order; all of them when `left_out` is empty.
std::vector<Triangle> kept_triangles(std::span<const Triangle> triangles,
                                     std::span<const char> left_out);

// `mesh` without the faces whose `removed` entry (one per face) is set, in place: the faces
// kept move down in order, their corners with them; vertices stay (some may be left
// without faces). O(corners).
void erase_faces(PolygonMesh& mesh, std::span<const char> removed);

}  // namespace spheremap
