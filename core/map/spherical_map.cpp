#include "core/map/spherical_map.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>

#include "core/map/map_session.h"
#include "core/mesh/spatial_order.h"

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

std::string_view to_string(Quality quality) {
  switch (quality) {
    case Quality::kFast:
      return "fast";
    case Quality::kStandard:
      return "standard";
    case Quality::kHigh:
      return "high";
  }
  return "unknown";
}

std::optional<Quality> parse_quality(std::string_view name) {
  for (Quality q : {Quality::kFast, Quality::kStandard, Quality::kHigh})
    if (name == to_string(q)) return q;
  return std::nullopt;
}

OrientedTriangles oriented_triangles(const PolygonMesh& mesh) {
  FanTriangulation fan = fan_triangulate(mesh);
  OrientedTriangles out{std::move(fan.triangles), false, fan.conflicting_faces};
  out.inward = runs_inward(mesh.positions, out.triangles);
  if (out.inward)
    for (Triangle& t : out.triangles) std::swap(t[1], t[2]);
  return out;
}

MappingInput mapping_input(const PolygonMesh& input, const std::vector<uint32_t>& order) {
  MappingInput out{reordered(input, order), {}};
  center_and_scale(out.mesh.positions);
  out.oriented = oriented_triangles(out.mesh);
  out.oriented.triangles = canonical_triangles(out.oriented.triangles, out.mesh.vertex_count());
  return out;
}

std::vector<char> filled_mask(std::span<const Triangle> triangles,
                              std::span<const Triangle> filled) {
  if (filled.empty()) return {};
  auto sorted = [](Triangle t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<Triangle> keys;
  keys.reserve(filled.size());
  for (const Triangle& t : filled) keys.push_back(sorted(t));
  std::sort(keys.begin(), keys.end());
  std::vector<char> mask(triangles.size(), 0);
  for (size_t k = 0; k < triangles.size(); ++k)
    mask[k] = std::binary_search(keys.begin(), keys.end(), sorted(triangles[k]));
  return mask;
}

namespace {

// Per triangle of `triangles`: filled_weight when it is one of `filled`, 1 otherwise; empty
// when nothing was filled or the weight is 1.
std::vector<double> triangle_weights(std::span<const Triangle> triangles,
                                     std::span<const Triangle> filled, double filled_weight) {
  if (filled.empty() || filled_weight == 1) return {};
  const std::vector<char> mask = filled_mask(triangles, filled);
  std::vector<double> weights(triangles.size(), 1.0);
  for (size_t k = 0; k < triangles.size(); ++k)
    if (mask[k]) weights[k] = filled_weight;
  return weights;
}

MapResult map_in_order(const MappingInput& input, const MapOptions& options,
                       const MapControl& control, std::chrono::steady_clock::time_point start,
                       std::span<const Triangle> filled) {
  MapSession session(options, control, start);
  MapResult result;
  const PolygonMesh& mesh = input.mesh;
  const OrientedTriangles& oriented = input.oriented;
  const std::vector<double> weights =
      triangle_weights(oriented.triangles, filled, std::clamp(options.filled_weight, 1e-3, 1.0));
  session.set_triangle_weights(weights);
  if (oriented.conflicting_faces)
    throw std::invalid_argument("cannot triangulate " + std::to_string(oriented.conflicting_faces) +
                                " polygons without duplicating an edge");
  result.inward = oriented.inward;
  if (options.method == Method::kPaper)
    map_paper(mesh, oriented.triangles, session, result);
  else
    map_coarse_to_fine(mesh, oriented.triangles, session, result);
  result.stopped_in = session.stopped_in();
  if (result.stop_reason == StopReason::kCancelled) return result;

  session.report({.stage = "verify"});
  const double verify_start = session.elapsed();
  result.check = verify_map(result.sphere, oriented.triangles, mesh, oriented.inward);
  result.verify_seconds = session.elapsed() - verify_start;
  // A stage the clock cut short (the finest level's optimization, the polish) leaves a
  // complete map, even a bijective one, that is not the map the options asked for: the
  // heart plate at a 5 s limit was reported bijective in double and folded in float32.
  result.stopped_in = session.stopped_in();
  if (!result.stopped_in.empty() && result.stop_reason != StopReason::kCancelled)
    result.stop_reason = session.stop_reason();
  // A map stopped by the time limit keeps that reason even when it happens to be
  // bijective: it is not the map the options asked for.
  if (result.check.bijective && result.stop_reason != StopReason::kTimeLimit)
    result.stop_reason = StopReason::kBijective;
  else if (result.stop_reason == StopReason::kBijective)
    result.stop_reason = StopReason::kFoldsRemain;
  return result;
}

}  // namespace

MapResult map_to_sphere(const PolygonMesh& input, const MapOptions& options,
                        const MapControl& control, std::span<const Triangle> filled) {
  // Map a copy in a cache-friendly vertex order, centred and scaled to the unit ball
  // (the map does not depend on the mesh's placement or units; its arithmetic would),
  // positions back in the input's order. On
  // the hardest shapes the outcome hinges on tiny perturbations (which vertex labels
  // which tetrahedron corner, summation orders), so a map that folds in every setting
  // of the first order is tried again (Lai-Cheng levels) in the input's own order; the
  // better of the two maps is returned.
  const auto start = control.clock_start.value_or(std::chrono::steady_clock::now());
  const std::vector<uint32_t> morton = morton_order(input.positions);
  std::vector<uint32_t> identity(input.vertex_count());
  std::iota(identity.begin(), identity.end(), 0u);
  MapResult best;
  size_t attempts = 0, iterations = 0;
  double work = 0;
  const std::vector<uint32_t>* orders[] = {&morton, &identity};
  for (const std::vector<uint32_t>* order : orders) {
    MapOptions attempt_options = options;
    attempt_options.attempts = std::max<size_t>(1, options.attempts - attempts);
    if (order != &morton) {
      attempt_options.direct_iterations = 0;  // tried already
      attempt_options.optimize = false;
    }
    // The filled triangles in the order's vertex ids.
    std::vector<uint32_t> new_id(order->size());
    for (uint32_t k = 0; k < order->size(); ++k) new_id[(*order)[k]] = k;
    std::vector<Triangle> renamed;
    renamed.reserve(filled.size());
    for (const Triangle& t : filled)
      if (t[0] < new_id.size() && t[1] < new_id.size() && t[2] < new_id.size())
        renamed.push_back({new_id[t[0]], new_id[t[1]], new_id[t[2]]});
    MapResult result =
        map_in_order(mapping_input(input, *order), attempt_options, control, start, renamed);
    attempts += result.attempts, iterations += result.iterations;
    work += result.fine_iteration_equivalents;
    result.attempts = attempts, result.iterations = iterations;
    result.fine_iteration_equivalents = work;
    if (!result.sphere.empty()) {
      std::vector<Vec3> sphere(result.sphere.size());
      for (size_t k = 0; k < order->size(); ++k) sphere[(*order)[k]] = result.sphere[k];
      result.sphere.swap(sphere);
    }
    const bool better = best.sphere.empty() || result.check.bijective ||
                        (!result.sphere.empty() && result.check.folds < best.check.folds);
    if (better || result.stop_reason == StopReason::kCancelled) {
      best = std::move(result);
    } else {
      best.attempts = attempts, best.iterations = iterations;
      best.fine_iteration_equivalents = work;
    }
    if (best.check.bijective || options.method == Method::kPaper || attempts >= options.attempts ||
        best.stop_reason == StopReason::kCancelled || best.stop_reason == StopReason::kTimeLimit)
      break;
  }
  return best;
}

}  // namespace spheremap
