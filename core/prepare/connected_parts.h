// The parts of an asset: the connected components of its welded mesh (vertices joined by
// faces), each as a mesh of its own. An asset of several parts maps every part that is
// closed genus 0 on a sphere of its own (prepare "parts"), so each part must be checked,
// and later mapped, alone.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh/stop_check.h"
#include "core/mesh/submesh.h"  // MeshPart: the part, its vertices in first-use order

namespace spheremap {

// Every connected component of `mesh` with at least one face, largest first by faces (ties:
// the one whose first face comes first), faces in the whole's order. Unreferenced vertices
// belong to no part. `stop` (may be null) is asked as it goes. O(vertices + corners).
std::vector<MeshPart> connected_parts(const PolygonMesh& mesh, const StopCheck* stop = nullptr);

// The same parts, in the same order, as the faces of each (face ids of `mesh`, ascending).
std::vector<std::vector<uint32_t>> connected_part_faces(const PolygonMesh& mesh,
                                                        const StopCheck* stop = nullptr);

}  // namespace spheremap
