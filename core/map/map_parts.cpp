#include "core/map/map_parts.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/mesh/sphere_geometry.h"
#include "core/prepare/connected_parts.h"

namespace spheremap {
namespace {

// The part's surface area and area-weighted centroid (its vertices' mean when it has no
// area), which place its sphere in outputs that show every part.
void place(MappedPart& part) {
  const PolygonMesh& mesh = part.mapped.prepared.welded.mesh;
  double area = 0;
  Vec3 centroid;
  for (const Triangle& t : fan_triangulate(mesh).triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double w = 0.5 * norm(cross(b - a, c - a));
    area += w;
    centroid += (a + b + c) * (w / 3);
  }
  if (area > 0 && std::isfinite(area)) {
    centroid *= 1 / area;
  } else {
    centroid = {};
    for (const Vec3& p : mesh.positions) centroid += p;
    centroid *= 1.0 / static_cast<double>(mesh.positions.size());
  }
  part.center = centroid;
  part.surface_area = area;
  part.radius = std::sqrt(area / (4 * M_PI));
}

// Not a map: each vertex's direction from the part's centroid (a part the time limit left
// no time to start).
MapResult unmapped(const PolygonMesh& mesh, const Vec3& center) {
  MapResult map;
  map.stop_reason = StopReason::kTimeLimit;
  for (const Vec3& p : mesh.positions) map.sphere.push_back(normalized_or(p - center, {0, 0, 1}));
  return map;
}

void add_summary(DistortionSummary& total, const DistortionSummary& part, double weight) {
  total.mean += part.mean * weight;
  total.p99 = std::max(total.p99, part.p99);
  total.max = std::max(total.max, part.max);
}

// Area-weighted means and RMS over the parts; the parts' p99 and max at their largest.
QualityMetrics combined_quality(const std::vector<MappedPart>& parts) {
  QualityMetrics q;
  double area = 0, l2_squared = 0;
  for (const MappedPart& part : parts) area += part.surface_area;
  for (const MappedPart& part : parts) {
    const QualityMetrics& p = part.mapped.quality;
    const double w = area > 0 ? part.surface_area / area : 1.0 / parts.size();
    add_summary(q.area_log_ratio, p.area_log_ratio, w);
    add_summary(q.dilatation, p.dilatation, w);
    q.angle_error_degrees += p.angle_error_degrees * w;
    l2_squared += p.stretch_l2 * p.stretch_l2 * w;
    q.stretch_linf = std::max(q.stretch_linf, p.stretch_linf);
    q.measured_triangles += p.measured_triangles;
    q.skipped_triangles += p.skipped_triangles;
  }
  q.stretch_l2 = std::sqrt(l2_squared);
  return q;
}

// The worst of the parts' stop reasons (a time limit first: the whole did not finish).
StopReason combined_stop(const std::vector<MappedPart>& parts) {
  StopReason worst = StopReason::kBijective;
  for (const MappedPart& part : parts) {
    const StopReason r = part.mapped.map.stop_reason;
    if (r == StopReason::kTimeLimit) return r;
    if (r != StopReason::kBijective) worst = r;
  }
  return worst;
}

}  // namespace

MappedMesh map_parts(PreparedMesh prepared, const MapOptions& options, const MapControl& control) {
  const auto start = std::chrono::steady_clock::now();
  MappedMesh whole;
  whole.prepared = std::move(prepared);
  const PolygonMesh& mesh = whole.prepared.welded.mesh;
  std::vector<MeshPart> split = connected_parts(mesh);
  MapResult& map = whole.map;
  map.sphere.assign(mesh.vertex_count(), Vec3{});
  map.check.min_signed_area = INFINITY;
  map.check.bijective = true;
  whole.float32_check = map.check;
  map.inward = true;
  for (MeshPart& piece : split) {
    MappedPart part;
    part.whole_vertex = std::move(piece.vertex);
    PreparedMesh alone;
    alone.welded.mesh = std::move(piece.mesh);
    alone.topology = analyze_topology(alone.welded.mesh);
    alone.preparation = whole.prepared.preparation;
    part.mapped.prepared = std::move(alone);
    place(part);
    // One time limit for all: every part counts from the same start (the caller's, else
    // this call's), so each gets what the parts before it left.
    MapControl part_control = control;
    if (!part_control.clock_start) part_control.clock_start = start;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - *part_control.clock_start)
            .count();
    if (options.time_limit_seconds > 0 && elapsed >= options.time_limit_seconds) {
      const PolygonMesh& part_mesh = part.mapped.prepared.welded.mesh;
      part.mapped.map = unmapped(part_mesh, part.center);
      part.mapped.map.check =
          check_map(part.mapped.map.sphere, oriented_triangles(part_mesh).triangles);
      part.mapped.map.stopped_in = "waiting";
    } else {
      MappedMesh mapped = map_prepared(std::move(part.mapped.prepared), options, part_control);
      if (mapped.map.sphere.empty()) {  // cancelled
        map.sphere.clear();
        map.stop_reason = StopReason::kCancelled;
        return whole;
      }
      part.mapped = std::move(mapped);
    }
    const MapResult& m = part.mapped.map;
    for (size_t v = 0; v < part.whole_vertex.size(); ++v)
      map.sphere[part.whole_vertex[v]] = m.sphere[v];
    add_check(map.check, part.mapped.map.check);
    add_check(whole.float32_check, part.mapped.float32_check);
    map.attempts = std::max(map.attempts, m.attempts);
    map.iterations += m.iterations;
    map.hierarchy_rounds += m.hierarchy_rounds;
    map.polish_rounds += m.polish_rounds;
    map.stretch_vertex_updates += m.stretch_vertex_updates;
    map.hierarchy_seconds += m.hierarchy_seconds;
    map.mapping_seconds += m.mapping_seconds;
    map.optimize_seconds += m.optimize_seconds;
    map.verify_seconds += m.verify_seconds;
    map.optimized = whole.parts.empty() ? m.optimized : map.optimized && m.optimized;
    map.inward = map.inward && m.inward;
    if (map.stopped_in.empty() && !m.stopped_in.empty())
      map.stopped_in = "part " + std::to_string(whole.parts.size()) + ": " + m.stopped_in;
    whole.metrics_seconds += part.mapped.metrics_seconds;
    whole.parts.push_back(std::move(part));
  }
  map.stop_reason = combined_stop(whole.parts);
  // A part left unmapped has no float32 check of its own: the whole is not certified.
  for (const MappedPart& part : whole.parts)
    if (part.mapped.float32_check.triangles == 0) whole.float32_check.bijective = false;
  whole.quality = combined_quality(whole.parts);
  return whole;
}

}  // namespace spheremap
