#include "core/map/map_parts.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "core/map/certification.h"
#include "core/map/map_check.h"
#include "core/map/part_copies.h"
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

// The members of `whole` that describe its parts together (pipeline.h), from whole.parts.
void combine(MappedMesh& whole) {
  MapResult& map = whole.map;
  map = MapResult{};
  map.sphere.assign(whole.prepared.welded.mesh.vertex_count(), Vec3{});
  map.check.min_signed_area = INFINITY;
  map.check.bijective = true;
  whole.float32_check = map.check;
  map.inward = true;
  map.optimized = true;
  for (size_t k = 0; k < whole.parts.size(); ++k) {
    const MappedPart& part = whole.parts[k];
    const MapResult& m = part.mapped.map;
    for (size_t v = 0; v < part.whole_vertex.size(); ++v)
      map.sphere[part.whole_vertex[v]] = m.sphere[v];
    add_check(map.check, m.check);
    add_check(whole.float32_check, part.mapped.float32_check);
    // A part left unmapped has no float32 check of its own: the whole is not certified.
    if (part.mapped.float32_check.triangles == 0) whole.float32_check.bijective = false;
    map.attempts = std::max(map.attempts, m.attempts);
    map.iterations += m.iterations;
    map.hierarchy_rounds += m.hierarchy_rounds;
    map.polish_rounds += m.polish_rounds;
    map.float32_rescued += m.float32_rescued;
    map.stretch_vertex_updates += m.stretch_vertex_updates;
    map.hierarchy_seconds += m.hierarchy_seconds;
    map.mapping_seconds += m.mapping_seconds;
    map.optimize_seconds += m.optimize_seconds;
    map.verify_seconds += m.verify_seconds;
    map.optimized = map.optimized && m.optimized;
    map.inward = map.inward && m.inward;
    if (map.stopped_in.empty() && !m.stopped_in.empty())
      map.stopped_in = "part " + std::to_string(k) + ": " + m.stopped_in;
  }
  map.stop_reason = combined_stop(whole.parts);
  whole.quality = combined_quality(whole.parts);
}

// Parts whose map ran to the end but is not certified (folds left, or float32 rounding
// breaks it) are left out like parts that cannot map, with the reason, when some other
// part is certified: the asset is served where it can be. `whole` keeps the others.
void leave_out_uncertified(MappedMesh& whole) {
  std::vector<char> keep(whole.parts.size());
  size_t kept = 0;
  for (size_t k = 0; k < whole.parts.size(); ++k) {
    const MappedMesh& part = whole.parts[k].mapped;
    keep[k] = part.map.stop_reason == StopReason::kTimeLimit ||
              certify(part, part.float32_check).certified;
    kept += keep[k];
  }
  if (kept == whole.parts.size() || kept == 0) return;
  // The reports of the parts that mapped, in the same order as whole.parts.
  std::vector<PartReport*> reports;
  for (PartReport& report : whole.prepared.parts)
    if (report.mappable()) reports.push_back(&report);
  WeldResult& welded = whole.prepared.welded;
  std::vector<uint32_t> new_id(welded.mesh.vertex_count(), kUnreferenced);
  PolygonMesh mesh;
  std::vector<MappedPart> parts;
  std::vector<uint32_t> corners;
  std::vector<size_t> kept_index(whole.parts.size(), 0);  // copies name their original by it
  for (size_t k = 0, next = 0; k < whole.parts.size(); ++k)
    if (keep[k]) kept_index[k] = next++;
  for (size_t k = 0; k < whole.parts.size(); ++k) {
    MappedPart& part = whole.parts[k];
    if (part.copy_of) part.copy_of = kept_index[*part.copy_of];  // originals are certified: kept
    if (!keep[k]) {
      if (k < reports.size())
        reports[k]->failures = {
            {"not_certified", "its map is not certified: " +
                                  certify(part.mapped, part.mapped.float32_check).detail}};
      continue;
    }
    const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
    for (uint32_t& w : part.whole_vertex) {
      new_id[w] = first + static_cast<uint32_t>(&w - part.whole_vertex.data());
      mesh.positions.push_back(welded.mesh.positions[w]);
      w = new_id[w];
    }
    const PolygonMesh& own = part.mapped.prepared.welded.mesh;
    for (size_t f = 0; f < own.face_count(); ++f) {
      corners.clear();
      for (uint32_t v : own.face(f)) corners.push_back(first + v);
      mesh.add_face(corners);
    }
    parts.push_back(std::move(part));
  }
  for (uint32_t& w : welded.input_to_welded)
    if (w != kUnreferenced) w = new_id[w];
  rename_triangles(whole.prepared.filled, new_id);
  welded.mesh = std::move(mesh);
  whole.prepared.topology = analyze_topology(welded.mesh);
  whole.parts = std::move(parts);
}

// Tolerance of a copy's fit (part_copies.h), relative to the part's size: copies a text
// file wrote with 6 to 7 digits are still copies.
constexpr double kCopyTolerance = 1e-5;

// At most this many earlier parts are fitted to a part (copied_map).
constexpr size_t kCopyCandidates = 16;

// The map of `part` as the map of an earlier certified part with the same faces turned onto
// it (part_copies.h), measured and checked like any map; nullopt when no earlier part fits
// or the turned map does not pass its own certification (then the part is mapped).
std::optional<MappedMesh> copied_map(const PreparedMesh& part, const std::vector<MappedPart>& done,
                                     const std::vector<size_t>& candidates,
                                     const MapOptions& options, size_t& source) {
  const PolygonMesh& mesh = part.welded.mesh;
  // The first few only: candidates of one shape_hash are copies of one another but for
  // near-collisions, so a copy's original is among them (the bound keeps a part's work
  // small whatever the asset).
  for (size_t j : std::span(candidates).first(std::min(candidates.size(), kCopyCandidates))) {
    const MappedMesh& earlier = done[j].mapped;
    const PolygonMesh& earlier_mesh = earlier.prepared.welded.mesh;
    if (!same_faces(earlier_mesh, earlier.prepared.filled, mesh, part.filled)) continue;
    const std::optional<Rotation> turn =
        rotation_onto(earlier_mesh.positions, mesh.positions, kCopyTolerance);
    if (!turn) continue;
    MappedMesh copy;
    copy.prepared = part;
    MapResult& map = copy.map;
    const MapResult& from = earlier.map;
    map.stop_reason = from.stop_reason;
    map.attempts = from.attempts;
    map.optimized = from.optimized;
    map.inward = from.inward;
    map.sphere.reserve(from.sphere.size());
    for (const Vec3& q : from.sphere) map.sphere.push_back(normalized_or(rotate(*turn, q), q));
    const auto start = std::chrono::steady_clock::now();
    const OrientedTriangles oriented = oriented_triangles(mesh);
    map.check = verify_map(map.sphere, oriented.triangles, mesh, oriented.inward);
    map.verify_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (oriented.inward != from.inward || !clean(map.check)) continue;
    measure_map(copy, options);
    if (!certify(copy, copy.float32_check).certified) continue;
    source = j;
    return copy;
  }
  return std::nullopt;
}

// copied_map, its seconds added to `seconds` whether it found a copy or not, but for the
// found copy's check and metrics (counted in verify and metrics, as a mapped part's are).
std::optional<MappedMesh> timed_copied_map(const PreparedMesh& part,
                                           const std::vector<MappedPart>& done,
                                           const std::vector<size_t>& candidates,
                                           const MapOptions& options, size_t& source,
                                           double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  std::optional<MappedMesh> copy = copied_map(part, done, candidates, options, source);
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (copy) seconds -= copy->map.verify_seconds + copy->metrics_seconds;
  return copy;
}

// The parts of `split` in the order of their reports (PartReport::welded_vertex), so that
// reports and maps pair up by order even where an envelope changed a part's size; as split
// when the reports do not name every part.
void order_as_reported(std::vector<MeshPart>& split, const std::vector<PartReport>& reports,
                       size_t vertex_count) {
  std::vector<uint32_t> part_of(vertex_count, kUnreferenced);
  for (size_t k = 0; k < split.size(); ++k)
    for (uint32_t v : split[k].vertex) part_of[v] = static_cast<uint32_t>(k);
  std::vector<uint32_t> order;
  std::vector<char> taken(split.size(), 0);
  for (const PartReport& report : reports) {
    if (!report.mappable() || report.welded_vertex >= vertex_count) continue;
    const uint32_t k = part_of[report.welded_vertex];
    if (k == kUnreferenced || taken[k]) return;
    taken[k] = 1;
    order.push_back(k);
  }
  if (order.size() != split.size()) return;
  std::vector<MeshPart> ordered;
  for (uint32_t k : order) ordered.push_back(std::move(split[k]));
  split = std::move(ordered);
}

}  // namespace

MappedMesh map_parts(PreparedMesh prepared, const MapOptions& options, const MapControl& control) {
  const auto start = std::chrono::steady_clock::now();
  MappedMesh whole;
  whole.prepared = std::move(prepared);
  std::vector<MeshPart> split = connected_parts(whole.prepared.welded.mesh);
  order_as_reported(split, whole.prepared.parts, whole.prepared.welded.mesh.vertex_count());
  // Per vertex of the whole with a filled triangle: its part and its id there.
  std::vector<uint32_t> part_of, local_id;
  if (!whole.prepared.filled.empty()) {
    part_of.assign(whole.prepared.welded.mesh.vertex_count(), kUnreferenced);
    local_id.assign(part_of.size(), kUnreferenced);
    for (uint32_t k = 0; k < split.size(); ++k)
      for (uint32_t v = 0; v < split[k].vertex.size(); ++v)
        part_of[split[k].vertex[v]] = k, local_id[split[k].vertex[v]] = v;
  }
  // The certified parts mapped so far, by faces_hash and shape_hash: where a copy finds
  // its original.
  std::unordered_map<uint64_t, std::vector<size_t>> by_faces;
  double copies_seconds = 0;
  for (MeshPart& piece : split) {
    MappedPart part;
    part.whole_vertex = std::move(piece.vertex);
    PreparedMesh alone;
    alone.welded.mesh = std::move(piece.mesh);
    for (const Triangle& t : whole.prepared.filled)
      if (part_of[t[0]] == whole.parts.size())
        alone.filled.push_back({local_id[t[0]], local_id[t[1]], local_id[t[2]]});
    alone.topology = analyze_topology(alone.welded.mesh);
    alone.preparation = whole.prepared.preparation;
    part.mapped.prepared = std::move(alone);
    place(part);
    // One time limit for all: every part counts from the same start (the caller's, else
    // this call's), so each gets what the parts before it left.
    MapControl part_control = control;
    if (!part_control.clock_start) part_control.clock_start = start;
    if (control.on_progress)
      part_control.on_progress = [&control, k = whole.parts.size() + 1,
                                  n = split.size()](const MapProgress& p) {
        MapProgress of_part = p;
        of_part.part = k;
        of_part.parts = n;
        control.on_progress(of_part);
      };
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - *part_control.clock_start)
            .count();
    const PolygonMesh& own = part.mapped.prepared.welded.mesh;
    const uint64_t faces =
        faces_hash(own, part.mapped.prepared.filled) * 31 + shape_hash(own.positions);
    const auto earlier = by_faces.find(faces);
    size_t source = 0;
    std::optional<MappedMesh> copy;
    if (options.time_limit_seconds > 0 && elapsed >= options.time_limit_seconds) {
      const PolygonMesh& part_mesh = part.mapped.prepared.welded.mesh;
      part.mapped.map = unmapped(part_mesh, part.center);
      part.mapped.map.check =
          check_map(part.mapped.map.sphere, oriented_triangles(part_mesh).triangles);
      part.mapped.map.stopped_in = "waiting";
    } else if (earlier != by_faces.end() &&
               (copy = timed_copied_map(part.mapped.prepared, whole.parts, earlier->second, options,
                                        source, copies_seconds))) {
      part.mapped = std::move(*copy);
      part.copy_of = source;
      // Checked, not mapped: its progress is its check's.
      if (part_control.on_progress)
        part_control.on_progress({.stage = "verify", .elapsed_seconds = elapsed});
    } else {
      MappedMesh mapped = map_prepared(std::move(part.mapped.prepared), options, part_control);
      if (mapped.map.sphere.empty()) {  // cancelled
        whole.map.stop_reason = StopReason::kCancelled;
        return whole;
      }
      part.mapped = std::move(mapped);
      if (certify(part.mapped, part.mapped.float32_check).certified)
        by_faces[faces].push_back(whole.parts.size());
    }
    whole.metrics_seconds += part.mapped.metrics_seconds;
    whole.parts.push_back(std::move(part));
  }
  leave_out_uncertified(whole);
  combine(whole);
  whole.map.copies_seconds = copies_seconds;
  return whole;
}

}  // namespace spheremap
