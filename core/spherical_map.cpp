#include "core/spherical_map.h"

#include <algorithm>
#include <stdexcept>

#include "core/map_session.h"

namespace spheremap {

std::string_view to_string(StopReason reason) {
  switch (reason) {
    case StopReason::kBijective:
      return "bijective";
    case StopReason::kFoldsRemain:
      return "folds_remain";
    case StopReason::kIterationLimit:
      return "iteration_limit";
    case StopReason::kTimeLimit:
      return "time_limit";
    case StopReason::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

OrientedTriangles oriented_triangles(const PolygonMesh& mesh) {
  FanTriangulation fan = fan_triangulate(mesh);
  OrientedTriangles out{std::move(fan.triangles), false, fan.conflicting_faces};
  out.inward = signed_volume(mesh.positions, out.triangles) < 0;
  if (out.inward)
    for (Triangle& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

MapResult map_to_sphere(const PolygonMesh& mesh, const MapOptions& options,
                        const MapControl& control) {
  MapSession session(options, control);
  MapResult result;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  if (oriented.conflicting_faces)
    throw std::invalid_argument("cannot triangulate " + std::to_string(oriented.conflicting_faces) +
                                " polygons without duplicating an edge");
  result.inward = oriented.inward;
  if (options.method == Method::kPaper)
    map_paper(mesh, oriented.triangles, session, result);
  else
    map_coarse_to_fine(mesh, oriented.triangles, session, result);
  if (result.stop_reason == StopReason::kCancelled) return result;

  session.report({.stage = "verify"});
  const double verify_start = session.elapsed();
  result.check = verify_map(result.sphere, oriented.triangles, mesh, oriented.inward);
  result.verify_seconds = session.elapsed() - verify_start;
  if (result.check.bijective)
    result.stop_reason = StopReason::kBijective;
  else if (result.stop_reason == StopReason::kBijective)
    result.stop_reason = StopReason::kFoldsRemain;
  return result;
}

}  // namespace spheremap
