#include "core/outputs/report_json.h"

#include <algorithm>
#include <cstdio>

#include "core/map/certification.h"
#include "core/mesh/counted.h"

namespace spheremap {
namespace {

nlohmann::json summary_json(const DistortionSummary& s) {
  return {{"mean", s.mean}, {"p99", s.p99}, {"max", s.max}};
}

}  // namespace

namespace {

// An envelope's figures: lengths in model units and, for the distances, relative to the
// diagonal of what it wraps.
void add_envelope(nlohmann::json& out, const EnvelopeReport& e) {
  out["voxel_size"] = e.voxel_size;
  out["offset"] = e.offset;
  out["offset_relative"] = e.diagonal > 0 ? e.offset / e.diagonal : 0.0;
  out["grid"] = {e.grid[0], e.grid[1], e.grid[2]};
  out["solid_voxels"] = e.solid_voxels;
  out["topology_rule"] = e.rule;
  out["handles_cut"] = e.handles_cut;
  out["handles_filled"] = e.handles_filled;
  out["voxels_changed"] = e.voxels_changed;
  out["largest_change_voxels"] = e.largest_change_voxels;
  out["voxel_surface_faces"] = e.voxel_faces;
  out["envelope_faces"] = e.faces;
  out["envelope_hausdorff"] = e.hausdorff;
  out["envelope_rms"] = e.rms;
  out["envelope_to_original"] = e.envelope_to_original;
  out["original_to_envelope"] = e.original_to_envelope;
}

}  // namespace

nlohmann::json preparation_json(const PreparationReport& p) {
  nlohmann::json out = {{"method", prepare_method_name(p.method)},
                        {"input_faces", p.input_faces},
                        {"collapsed_faces_dropped", p.collapsed_faces},
                        {"faces_shortened", p.shortened_faces},
                        {"duplicate_faces_dropped", p.duplicate_faces},
                        {"t_junctions_zipped", p.t_junctions_zipped},
                        {"faces_flipped", p.flipped_faces},
                        {"parts_reoriented", p.reoriented_parts},
                        {"weld_tolerance", p.weld_tolerance},
                        {"non_manifold_vertices_split", p.vertices_split},
                        {"non_manifold_edges_split", p.edges_split},
                        {"walls_doubled", p.walls_doubled},
                        {"holes_filled", p.holes_filled},
                        {"faces_added", p.faces_added},
                        {"vertices_added", p.vertices_added},
                        {"holes_left", p.holes_left},
                        {"largest_fill", p.largest_fill},
                        {"sheets_doubled", p.sheets_doubled},
                        {"open_parts_cut", p.open_parts_cut},
                        {"handles_closed", p.handles_closed},
                        {"handles_opened", p.handles_opened},
                        {"handles_left", p.handles_left},
                        {"largest_handle_cycle", p.largest_handle_cycle},
                        {"farthest_handle_fill", p.farthest_handle_fill}};
  if (p.method == PrepareMethod::kAuto) out["decided"] = p.decided;
  if (p.method == PrepareMethod::kWrap || p.decided == "wrap") add_envelope(out, p.envelope);
  return out;
}

nlohmann::json fix_json(const Fix& fix) {
  return {{"option", fix.option},
          {"value", nlohmann::json::parse(fix.value, nullptr, false)},
          {"effect", fix.effect}};
}

std::vector<ValidationFailure> input_failures(const PreparedMesh& prepared,
                                              const GltfReadStats* gltf) {
  std::vector<ValidationFailure> failures = remaining_failures(prepared);
  // Every face dropped by the cleaning (the Draco test data's degenerate_mesh.obj: one face
  // on three equal positions) was refused as "mesh has no faces": say where they went.
  const PreparationReport& done = prepared.preparation;
  if (done.input_faces > 0)
    for (ValidationFailure& f : failures)
      if (f.check == "empty")
        f.message = "mesh has no faces left: the cleaning dropped all " +
                    counted(done.input_faces, "face") + " (" +
                    std::to_string(done.collapsed_faces) +
                    " with fewer than 3 distinct corners once equal positions are welded, " +
                    std::to_string(done.duplicate_faces) + " exact duplicates)";
  // Vertices and no faces at all (a PLY's `element face 0`, an OBJ of `v` lines): a point
  // cloud, which is not what the map is for.
  const size_t input_vertices = prepared.welded.input_to_welded.size();
  if (done.input_faces == 0 && input_vertices > 0)
    for (ValidationFailure& f : failures)
      if (f.check == "empty")
        f.message = "the file is a point cloud (" + counted(input_vertices, "point") +
                    ", no faces): spheremap maps triangle surfaces";
  // Under "parts", none of the parts maps alone: say what the largest few fail.
  if (!prepared.parts.empty() && prepared.parts_left_out() == prepared.parts.size())
    for (ValidationFailure& f : failures)
      if (f.check == "components") {
        f.message += "; none of its parts maps alone:";
        const size_t shown = std::min<size_t>(prepared.parts.size(), 3);
        for (size_t k = 0; k < shown; ++k)
          f.message += (k ? "; part " : " part ") + std::to_string(k) + " (" +
                       std::to_string(prepared.parts[k].faces) +
                       " faces): " + prepared.parts[k].failures.front().message;
        if (shown < prepared.parts.size())
          f.message += "; and " + std::to_string(prepared.parts.size() - shown) + " more";
      }
  // Under exact or repair: prepare=parts where two parts or more map alone (each checked).
  const size_t parts_that_map = prepared.parts.size() - prepared.parts_left_out();
  if (!maps_by_parts(prepared.preparation.method) && parts_that_map >= 2)
    for (ValidationFailure& f : failures)
      if (f.check == "components")
        f.fix = {"prepare", "\"parts\"",
                 "maps " +
                     std::string(parts_that_map == prepared.parts.size()
                                     ? "every one"
                                     : std::to_string(parts_that_map)) +
                     " of its " + std::to_string(prepared.parts.size()) +
                     " parts on a sphere of its own (each checked: closed, manifold, genus 0)"};
  // Offer largest_component only when its part maps; otherwise say why it would not.
  const auto& largest = prepared.largest_component_failures;
  for (ValidationFailure& f : failures)
    if (f.fix.option == "largest_component" && !largest.empty()) {
      f.fix = {};
      f.message += "; the largest alone (" + std::to_string(prepared.largest_component_faces) +
                   " faces) cannot be mapped either: " + largest.front().message;
    }
  // A weld tolerance that was tried and closes the surface.
  if (prepared.closing_weld_tolerance > 0)
    for (ValidationFailure& f : failures)
      if (f.check == "boundary" && f.fix.empty()) {
        char value[32];
        std::snprintf(value, sizeof value, "%g", prepared.closing_weld_tolerance);
        f.fix = {"weld_tolerance", value,
                 std::string("welds vertices closer than ") + value +
                     " of the bounding-box diagonal, which closes it (tried: it then maps)"};
      }
  // A hole-fill bound that was tried and fills the holes left for their size.
  if (prepared.closing_hole_fill > 0)
    for (ValidationFailure& f : failures)
      if (f.check == "boundary" && f.fix.empty()) {
        const PreparationReport& r = prepared.preparation;
        char value[32], share[32];
        std::snprintf(value, sizeof value, "%g", prepared.closing_hole_fill);
        std::snprintf(share, sizeof share, "%.3g", r.largest_left_fill);
        f.message += "; " + std::to_string(r.holes_too_large) +
                     (r.holes_too_large == 1 ? " hole was" : " holes were") +
                     " left open for its size: the largest fill would be " + share +
                     " of its part's surface";
        f.fix = {"max_hole_fill", value,
                 std::string("fills holes up to ") + value +
                     " of their part's surface, which closes it (tried: it then maps)"};
      }
  if (gltf) suggest_gltf_fixes(failures, *gltf);
  return failures;
}

namespace {

// What a topology report says of a surface's shape, as JSON (the fields `info` prints).
nlohmann::json shape_json(const TopologyReport& r) {
  nlohmann::json sizes = nlohmann::json::object();
  for (auto [corners, count] : r.face_sizes) sizes[std::to_string(corners)] = count;
  const long long genus = r.genus();
  return {
      {"vertices", r.vertices},
      {"edges", r.edges},
      {"faces", r.faces},
      {"face_sizes", sizes},
      {"euler_characteristic", r.euler_characteristic},
      {"genus", genus >= 0 ? nlohmann::json(genus) : nlohmann::json(nullptr)},
      {"closed", r.closed()},
      {"boundary_edges", r.boundary_edges},
      {"boundary_loops", r.boundary_loops},
      {"manifold", r.manifold()},
      {"non_manifold_edges", r.non_manifold_edges},
      {"non_manifold_vertices", r.non_manifold_vertices},
      {"faces_with_repeated_vertices", r.faces_with_repeated_vertices},
      {"inconsistently_oriented_edges", r.inconsistent_edges},
      {"orientation", r.inward ? "inward" : "outward"},
      {"components", r.component_vertices.size()},
      {"component_vertices", r.component_vertices},
      {"component_faces", r.component_faces},
      {"non_finite_vertices", r.non_finite_vertices},
      {"zero_area_faces", r.zero_area_faces},
  };
}

}  // namespace

nlohmann::json topology_json(const PreparedMesh& prepared, const GltfReadStats* gltf) {
  nlohmann::json failures = nlohmann::json::array();
  for (const ValidationFailure& f : input_failures(prepared, gltf)) {
    failures.push_back({{"check", f.check}, {"message", f.message}});
    if (!f.fix.empty()) failures.back()["fix"] = fix_json(f.fix);
  }
  nlohmann::json report = shape_json(prepared.topology);
  report["input_vertices"] = prepared.welded.input_to_welded.size();
  report["unreferenced_vertices"] = prepared.welded.unreferenced_vertices;
  report["mappable"] = failures.empty();
  report["failures"] = failures;
  report["preparation"] = preparation_json(prepared.preparation);
  // The top level is the mesh that is mapped (the input as prepared: cleaned, filled, cut
  // into parts or wrapped); "input" is the file as read, so a torus whose handle was closed
  // does not read as genus 0 alone.
  if (prepared.input_topology) report["input"] = shape_json(*prepared.input_topology);
  if (!prepared.parts.empty()) report["parts"] = parts_json(prepared, nullptr);
  // Only when there are some: reports of files read without leniency stay as they were.
  if (gltf && !gltf->warnings.empty()) report["warnings"] = gltf->warnings;
  return report;
}

nlohmann::json parts_json(const PreparedMesh& prepared, const MappedMesh* mapped) {
  nlohmann::json parts = nlohmann::json::array();
  size_t mapped_index = 0;
  std::vector<size_t> part_of_mapped;  // mapped index -> k (a copy names its original by k)
  for (size_t k = 0; k < prepared.parts.size(); ++k) {
    const PartReport& report = prepared.parts[k];
    nlohmann::json part = {{"part", k}, {"vertices", report.vertices}, {"faces", report.faces}};
    if (!report.mappable()) {
      part["mapped"] = false;
      part["check"] = report.failures.front().check;
      std::string reason = report.failures.front().message;
      for (size_t i = 1; i < report.failures.size(); ++i)
        reason += "; also " + report.failures[i].message;
      part["reason"] = reason;
    } else {
      part["mapped"] = true;
      if (report.wrapped) {  // kAuto: the part's envelope mapped in its place
        nlohmann::json envelope = {{"check", report.wrap_reasons.front().check}};
        std::string reason = report.wrap_reasons.front().message;
        for (size_t i = 1; i < report.wrap_reasons.size(); ++i)
          reason += "; also " + report.wrap_reasons[i].message;
        envelope["reason"] = reason;
        add_envelope(envelope, report.envelope);
        part["wrapped"] = std::move(envelope);
      }
      if (mapped && mapped_index < mapped->parts.size()) {
        const MappedPart& p = mapped->parts[mapped_index];
        const MapResult& m = p.mapped.map;
        part["bijective"] = certify(p.mapped, p.mapped.float32_check).certified;
        part["stop_reason"] = std::string(to_string(m.stop_reason));
        part["folds"] = m.check.folds;
        part["degenerate_triangles"] = m.check.degenerate;
        part["attempts"] = m.attempts;
        part["stretch"] = {{"l2", p.mapped.quality.stretch_l2},
                           {"linf", p.mapped.quality.stretch_linf}};
        part["area_distortion"] = summary_json(p.mapped.quality.area_log_ratio);
        part["sphere_center"] = {p.center.x, p.center.y, p.center.z};
        part["sphere_radius"] = p.radius;
        if (p.copy_of && *p.copy_of < part_of_mapped.size())
          part["copy_of"] = part_of_mapped[*p.copy_of];
      }
      part_of_mapped.push_back(k);
      ++mapped_index;
    }
    parts.push_back(std::move(part));
  }
  return parts;
}

nlohmann::json metrics_json(const MappedMesh& mapped, const MapOptions& options) {
  nlohmann::json out = map_metrics_json(mapped, options);
  // An asset of several parts: every part, mapped or left out with its reason.
  if (!mapped.prepared.parts.empty()) {
    out["parts"] = parts_json(mapped.prepared, &mapped);
    out["parts_mapped"] = mapped.prepared.parts.size() - mapped.prepared.parts_left_out();
    out["parts_left_out"] = mapped.prepared.parts_left_out();
  }
  return out;
}

nlohmann::json map_metrics_json(const MappedMesh& mapped, const MapOptions& options) {
  const MapResult& m = mapped.map;
  const QualityMetrics& q = mapped.quality;
  nlohmann::json levels = nlohmann::json::array();
  for (const LevelReport& l : m.levels)
    levels.push_back({{"vertices", l.vertices},
                      {"kernel_insertions", l.kernel_insertions},
                      {"failed_insertions", l.failed_insertions},
                      {"iterations", l.iterations},
                      {"repair_iterations", l.repair_iterations},
                      {"fallback", l.fallback},
                      {"folds", l.folds},
                      {"min_area", l.min_area},
                      {"optimize_sweeps", l.optimize_sweeps},
                      {"newton_steps", l.newton_steps},
                      {"energy", l.energy}});
  return {
      {"method", options.method == Method::kPaper ? "paper" : "coarse-to-fine"},
      {"preparation", preparation_json(mapped.prepared.preparation)},
      {"quality", std::string(to_string(options.quality))},
      {"optimized", m.optimized},
      // The certified verdict (double, float32; callers that write a file replace it with
      // the verdict on the file as written). The double-precision check alone is
      // bijective_double.
      {"bijective", certify(mapped, mapped.float32_check).certified},
      {"bijective_double", m.check.bijective},
      {"stop_reason", std::string(to_string(m.stop_reason))},
      {"stopped_in", m.stopped_in},
      {"vertices", mapped.prepared.topology.vertices},
      {"faces", mapped.prepared.topology.faces},
      {"triangles", m.check.triangles},
      {"folds", m.check.folds},
      {"nonconvex_polygons", m.check.nonconvex_polygons},
      {"degenerate_triangles", m.check.degenerate},
      {"min_spherical_area", m.check.min_signed_area},
      {"signed_area_sum", m.check.signed_area_sum},
      {"orientation", m.inward ? "inward" : "outward"},
      {"float32",
       {{"bijective", mapped.float32_check.bijective},
        {"folds", mapped.float32_check.folds},
        {"signed_area_sum", mapped.float32_check.signed_area_sum}}},
      {"attempts", m.attempts},
      {"iterations", m.iterations},
      {"fine_iteration_equivalents", m.fine_iteration_equivalents},
      {"hierarchy_rounds", m.hierarchy_rounds},
      {"polish_rounds", m.polish_rounds},
      {"float32_rescued", m.float32_rescued},
      {"levels", levels},
      // mean_abs_log: area-weighted mean of |log(sphere area share / surface area share)|,
      // the same number as "mean" (kept for readers of the first format).
      {"area_distortion",
       [&] {
         nlohmann::json a = summary_json(q.area_log_ratio);
         a["mean_abs_log"] = q.area_log_ratio.mean;
         return a;
       }()},
      {"angle_distortion",
       {{"dilatation", summary_json(q.dilatation)},
        {"corner_error_degrees", q.angle_error_degrees}}},
      {"stretch", {{"l2", q.stretch_l2}, {"linf", q.stretch_linf}}},
      {"measured_triangles", q.measured_triangles},
      {"skipped_triangles", q.skipped_triangles},
      {"seconds",
       {{"prepare", mapped.prepare_seconds},
        {"hierarchy", m.hierarchy_seconds},
        {"mapping", m.mapping_seconds},
        {"optimize", m.optimize_seconds},
        {"verify", m.verify_seconds},
        {"copies", m.copies_seconds},
        {"metrics", mapped.metrics_seconds}}},
  };
}

nlohmann::json without_timings(nlohmann::json metrics) {
  if (metrics.is_object()) {
    metrics.erase("seconds");
    for (auto& [key, value] : metrics.items()) value = without_timings(std::move(value));
  } else if (metrics.is_array()) {
    for (auto& value : metrics) value = without_timings(std::move(value));
  }
  return metrics;
}

}  // namespace spheremap
