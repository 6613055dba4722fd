// The envelope's checks: closed, 2-manifold, consistently oriented, one component, genus 0,
// as the map asks of any input (topology.h), on the mesh welded at exact positions as the
// map will weld it.
#pragma once

#include <string>

#include "core/mesh/mesh.h"

namespace spheremap {

// Empty when `mesh` maps; else the failed checks' messages, joined.
std::string envelope_failures(const PolygonMesh& mesh);

}  // namespace spheremap
