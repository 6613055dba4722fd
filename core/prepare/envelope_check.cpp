#include "core/prepare/envelope_check.h"

#include "core/mesh/topology.h"
#include "core/mesh/weld.h"

namespace spheremap {

std::string envelope_failures(const PolygonMesh& mesh) {
  const WeldResult welded = weld(mesh);
  if (welded.mesh.vertex_count() != mesh.vertex_count())
    return "two vertices of the envelope are at the same place";
  std::string out;
  for (const ValidationFailure& f : mapping_failures(analyze_topology(welded.mesh))) {
    if (!out.empty()) out += "; ";
    out += f.message;
  }
  return out;
}

}  // namespace spheremap
