#include "core/prepare/prepare_mesh.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "core/mesh/input_error.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/submesh.h"
#include "core/mesh/surface_distance.h"
#include "core/mesh/union_find.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/edge_pairing.h"
#include "core/prepare/edge_split.h"
#include "core/prepare/envelope_plan.h"
#include "core/prepare/face_cleanup.h"
#include "core/prepare/far_hole_fills.h"
#include "core/prepare/handle_closing.h"
#include "core/prepare/handle_opening.h"
#include "core/prepare/hole_cones.h"
#include "core/prepare/hole_filling.h"
#include "core/prepare/interior_walls.h"
#include "core/prepare/open_part_cuts.h"
#include "core/prepare/sheet_doubling.h"
#include "core/prepare/sheet_ends.h"
#include "core/prepare/vertex_copies.h"
#include "core/prepare/vertex_split.h"

namespace spheremap {
namespace {

// Drops every face outside the largest component (by faces) and the vertices left unused.
void keep_largest_component(WeldResult& welded) {
  PolygonMesh& mesh = welded.mesh;
  UnionFind sets(mesh.vertex_count());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  std::vector<size_t> faces_of(mesh.vertex_count(), 0);
  for (size_t f = 0; f < mesh.face_count(); ++f) ++faces_of[sets.find(mesh.face(f)[0])];
  const uint32_t keep =
      static_cast<uint32_t>(std::max_element(faces_of.begin(), faces_of.end()) - faces_of.begin());
  std::vector<uint32_t> faces;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (sets.find(mesh.face(f)[0]) == keep) faces.push_back(static_cast<uint32_t>(f));
  MeshPart kept = submesh(mesh, faces);
  std::vector<uint32_t> new_id(mesh.vertex_count(), kUnreferenced);
  for (uint32_t v = 0; v < kept.vertex.size(); ++v) new_id[kept.vertex[v]] = v;
  for (uint32_t& w : welded.input_to_welded)
    if (w != kUnreferenced) w = new_id[w];
  mesh = std::move(kept.mesh);
}

// Each primitive's face range [first_face, first_face + face_count) renumbered to the
// faces kept (source_face: per kept face, its old index, ascending).
void move_face_ranges(GltfAppearance& look, const std::vector<uint32_t>& source_face) {
  for (GltfAppearance::Primitive& p : look.primitives) {
    const auto first = std::lower_bound(source_face.begin(), source_face.end(), p.first_face);
    const auto last =
        std::lower_bound(source_face.begin(), source_face.end(), p.first_face + p.face_count);
    p.first_face = static_cast<uint32_t>(first - source_face.begin());
    p.face_count = static_cast<uint32_t>(last - first);
  }
}

// What build_envelope asks: should_stop or envelope_should_stop.
std::function<bool()> envelope_stop(const PrepareOptions& options) {
  return [&options] {
    return (options.should_stop && options.should_stop()) ||
           (options.envelope_should_stop && options.envelope_should_stop());
  };
}

}  // namespace

const char* prepare_method_name(PrepareMethod method) {
  switch (method) {
    case PrepareMethod::kExact:
      return "exact";
    case PrepareMethod::kRepair:
      return "repair";
    case PrepareMethod::kWrap:
      return "wrap";
    case PrepareMethod::kAuto:
      return "auto";
    case PrepareMethod::kParts:
      break;
  }
  return "parts";
}

size_t PreparedMesh::parts_left_out() const {
  return static_cast<size_t>(
      std::count_if(parts.begin(), parts.end(), [](const PartReport& p) { return !p.mappable(); }));
}

std::vector<ValidationFailure> remaining_failures(const PreparedMesh& prepared) {
  std::vector<ValidationFailure> failures = mapping_failures(prepared.topology);
  const bool some_part_maps = prepared.parts_left_out() < prepared.parts.size();
  if (maps_by_parts(prepared.preparation.method) && some_part_maps)
    std::erase_if(failures, [](const ValidationFailure& f) { return f.check == "components"; });
  for (ValidationFailure& f : failures)
    if (f.check == "genus" && !prepared.preparation.handles_stopped.empty())
      f.message += "; closing its handles stopped: " + prepared.preparation.handles_stopped;
  return failures;
}

namespace {

// What follows the weld: the largest part when asked, the topology report, and whether
// the largest part alone would map.
PreparedMesh prepare_welded(WeldResult welded, size_t input_faces, const PrepareOptions& options) {
  PreparedMesh prepared;
  StopCheck stop(&options.should_stop);
  prepared.welded = std::move(welded);
  if (options.largest_component) {
    prepared.input_topology = analyze_topology(prepared.welded.mesh, &stop);
    keep_largest_component(prepared.welded);
  }
  stop.check();
  prepared.topology = analyze_topology(prepared.welded.mesh, &stop);
  if (!prepared.input_topology) prepared.input_topology = prepared.topology;
  prepared.preparation.input_faces = input_faces;
  if (!options.largest_component && prepared.topology.component_vertices.size() > 1) {
    WeldResult largest = prepared.welded;
    keep_largest_component(largest);
    prepared.largest_component_faces = largest.mesh.face_count();
    prepared.largest_component_failures = mapping_failures(analyze_topology(largest.mesh, &stop));
  }
  return prepared;
}

}  // namespace

void rename_triangles(std::vector<Triangle>& triangles, std::span<const uint32_t> new_id) {
  size_t kept = 0;
  for (const Triangle& t : triangles) {
    Triangle renamed;
    bool known = true;
    for (int k = 0; k < 3; ++k) {
      renamed[k] = t[k] < new_id.size() ? new_id[t[k]] : kUnreferenced;
      known = known && renamed[k] != kUnreferenced;
    }
    if (known) triangles[kept++] = renamed;
  }
  triangles.resize(kept);
}

PreparedMesh prepare_mesh(const PolygonMesh& input, const PrepareOptions& options) {
  StopCheck stop(&options.should_stop);
  WeldResult welded = weld(input, options.weld_tolerance, &stop);
  stop.check();
  return prepare_welded(std::move(welded), input.face_count(), options);
}

namespace {

// A hole of an open genus-0 part is left for the part's back (far_hole_fills.h) when its
// fill would stand farther than this share of the part's diagonal from the part, as a
// handle's cut is taken where its fill stays within it (handle_closing.cpp).
constexpr double kFarHoleFill = 0.01;

// Holes closed by fills appended to the welded mesh (its input vertices are unchanged).
// Under kAuto with sheets doubled, a hole of an open genus-0 part whose fill would stand far
// is left open for the part's back; returns how many were so left.
size_t fill_small_holes(PreparedMesh& prepared, const PrepareOptions& options) {
  size_t kept_open = 0;
  if (prepared.topology.boundary_edges == 0 || options.max_hole_fill <= 0) return kept_open;
  StopCheck stop(&options.should_stop);
  KeepHoleOpen keep_open;
  if (options.method == PrepareMethod::kAuto && options.double_open_sheets)
    keep_open = [far = FarHoleFills(prepared.welded.mesh, kFarHoleFill), &kept_open](
                    std::span<const uint32_t> loop, std::span<const Triangle> fill) {
      if (!far(loop, fill)) return false;
      ++kept_open;
      return true;
    };
  const HoleFilling filled = fill_holes(prepared.welded.mesh, options.max_hole_fill, &stop,
                                        options.refine_hole_fills, keep_open);
  PreparationReport& report = prepared.preparation;
  report.holes_filled = filled.holes_filled;
  report.vertices_added = filled.vertices_added;
  report.faces_added = filled.faces_added;
  report.holes_left = filled.holes_left - filled.holes_kept_open;
  report.largest_fill = filled.largest_fill;
  report.holes_too_large = filled.holes_too_large;
  report.largest_left_fill = filled.largest_left_fill;
  if (filled.faces_added > 0) prepared.topology = analyze_topology(prepared.welded.mesh, &stop);
  return kept_open;
}

// Past this many parts that do not map (once open discs are doubled), kAuto wraps them as
// one envelope (a soup or a scatter of fragments: trimesh's 100-triangle soup.stl took
// 35 s part by part, 8 s whole, in session 31). Whole, an asset's inner parts are lost
// under its outer envelope: A-Frame's engine.glb (2,863 parts, 88 that do not map) stood
// 9.5% of its diagonal off wrapped whole (2.7 s), 1.7% with each of the 88 wrapped
// (8.1 s; session 55, when 64 was the bound).
constexpr size_t kMaxWrappedParts = 256;

// Past this many parts, and this many per part of the input as read, the parts are the
// preparation's shards, not the asset's: kAuto wraps the asset whole. vcglib's
// abominevole.off, one part of 50,706 faces with 30,361 non-manifold edges, came apart
// into 48,732 parts (each sliver doubled): mapped in 9 s, its remesh (a grid per part)
// took over a minute; wrapped whole, both take seconds. Kits of many parts (three.js's
// ww2-cityscene: 3,534) have as many parts as they were read with.
constexpr size_t kMaxShards = 4096;
constexpr size_t kShardsPerInputPart = 16;

bool shattered(const PreparedMesh& prepared) {
  const size_t parts = prepared.topology.component_vertices.size();
  const size_t read =
      prepared.input_topology ? prepared.input_topology->component_vertices.size() : parts;
  return parts > kMaxShards && parts > kShardsPerInputPart * std::max<size_t>(read, 1);
}

// Under kAuto, each part that is a disc whose hole was too large to fill closed by its own
// back (sheet_doubling.h), appended as fills are: exact where an envelope would not be.
void double_open_sheets(PreparedMesh& prepared, const PrepareOptions& options) {
  if (options.method != PrepareMethod::kAuto || !options.double_open_sheets ||
      prepared.topology.boundary_edges == 0)
    return;
  StopCheck stop(&options.should_stop);
  const SheetDoubling doubled = spheremap::double_open_sheets(prepared.welded.mesh, &stop);
  if (doubled.sheets_doubled == 0) return;
  PreparationReport& report = prepared.preparation;
  report.sheets_doubled = doubled.sheets_doubled;
  report.faces_added += doubled.faces_added;
  report.vertices_added += doubled.vertices_added;
  prepared.topology = analyze_topology(prepared.welded.mesh, &stop);
}

// Whether the input's faces that reach the welded mesh are its first faces, in order,
// corner for corner (fills come after): true unless a step reordered them.
bool input_faces_lead(const PolygonMesh& input, const WeldResult& welded) {
  size_t w = 0;
  for (size_t f = 0; f < input.face_count(); ++f) {
    if (welded.input_to_welded[input.face(f)[0]] == kUnreferenced) continue;
    if (w >= welded.mesh.face_count() || welded.mesh.face_size(w) != input.face_size(f))
      return false;
    const auto face = input.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      if (welded.input_to_welded[face[k]] != welded.mesh.face(w)[k]) return false;
    ++w;
  }
  return true;
}

// After welded vertices were copied (a handle's cut, a split vertex): each input face
// corner uses an input vertex whose welded vertex is the one its welded face has (faces as
// input_faces_lead). An input vertex all of whose corners moved to one copy is moved with
// them (an input seam already there needs no copy); the others get input copies.
void copy_cut_input_vertices(PolygonMesh& input, GltfAppearance* look, WeldResult& welded) {
  auto& to_welded = welded.input_to_welded;
  const uint32_t n = static_cast<uint32_t>(input.vertex_count());
  std::vector<char> keeps(n, 0), moved(n, 0);  // keeps: a corner of v stays where v welds
  auto for_each_corner = [&](auto&& visit) {
    size_t w = 0;
    for (size_t f = 0; f < input.face_count(); ++f) {
      if (to_welded[input.face(f)[0]] == kUnreferenced) continue;
      const auto welded_face = welded.mesh.face(w++);
      for (uint32_t slot = input.offsets[f]; slot < input.offsets[f + 1]; ++slot)
        visit(slot, welded_face[slot - input.offsets[f]]);
    }
  };
  for_each_corner([&](uint32_t slot, uint32_t target) {
    const uint32_t v = input.indices[slot];
    if (to_welded[v] == target) keeps[v] = 1;
  });
  std::unordered_map<uint64_t, uint32_t> copy_for;  // (input vertex, welded vertex) -> copy
  std::vector<uint32_t> source;
  for_each_corner([&](uint32_t slot, uint32_t target) {
    const uint32_t v = input.indices[slot];
    if (v >= n || to_welded[v] == target) return;
    if (!keeps[v] && !moved[v]) {
      to_welded[v] = target;
      moved[v] = 1;
      return;
    }
    const auto [it, added] =
        copy_for.emplace((uint64_t{v} << 32) | target, n + static_cast<uint32_t>(source.size()));
    if (added) {
      source.push_back(v);
      to_welded.push_back(target);
    }
    input.indices[slot] = it->second;
  });
  insert_vertex_copies(input, look, source, to_welded);
}

// Handles closed along short non-separating cycles (handle_closing.h): welded vertices on
// each cut copied, fills appended; the input gets the same copies, so every output in its
// layout has each side of the cut where the map put it. The welded mesh's faces below
// `own_faces` are the input's (fills come after them).
void close_short_handles(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                         const PrepareOptions& options, size_t own_faces) {
  if (options.max_handle_cycle <= 0) return;
  StopCheck stop(&options.should_stop);
  WeldResult& welded = prepared.welded;
  if (!input_faces_lead(input, welded)) return;
  // Under kAuto with backs, a part with holes and handles lends the handle search a closed
  // surface: its holes are coned for a while (hole_cones.h), the cones taken out below.
  const bool open_handles = options.method == PrepareMethod::kAuto && options.double_open_sheets;
  const HoleCones cones = open_handles && prepared.topology.boundary_edges > 0
                              ? cone_holes_of_parts_with_handles(welded.mesh, &stop)
                              : HoleCones{};
  HandleClosing closed =
      close_handles(welded.mesh, options.max_handle_cycle, &stop, kMaxHandles, own_faces);
  if (cones.faces > 0) {
    // The cones lie before the caps (appended after them): the caps move down.
    std::vector<char> cone(welded.mesh.face_count(), 0);
    std::fill_n(cone.begin() + static_cast<std::ptrdiff_t>(cones.first_face), cones.faces, 1);
    erase_faces(welded.mesh, cone);
    for (HandleClosing::ClosedPart& part : closed.closed_parts) part.first_fill -= cones.faces;
  }
  PreparationReport& report = prepared.preparation;
  report.handles_closed = closed.handles_closed;
  report.handles_left = closed.handles_left;
  report.largest_handle_cycle = closed.largest_cycle;
  report.farthest_handle_fill = closed.farthest_fill;
  report.faces_added += closed.faces_added;
  if (!closed.stopped.empty()) report.handles_stopped = closed.stopped.front().reason;
  prepared.handle_stops = closed.stopped;
  if (closed.handles_closed == 0 && cones.faces == 0) return;
  // Under kAuto with backs, a part whose caps stand far keeps its cuts open for its back
  // (as a far hole is left open: kFarHoleFill).
  if (open_handles && closed.handles_closed > 0) {
    const HandleOpening opened = open_far_handles(welded.mesh, closed, kFarHoleFill, &stop);
    report.handles_closed -= opened.handles_opened;
    report.handles_opened = opened.handles_opened;
    report.faces_added -= opened.faces_removed;
    report.farthest_handle_fill = opened.farthest_fill;
    report.vertices_split += opened.vertices_split;
  }
  copy_cut_input_vertices(input, look, welded);
  drop_unused_vertices(welded);  // the cones' apexes, and those only removed caps used
  prepared.topology = analyze_topology(welded.mesh, &stop);
}

// Under kAuto, each part that is genus 0 with several holes left open cut into a disc
// (open_part_cuts.h), for double_open_sheets to close by its back: welded vertices on the
// paths copied; the input gets the same copies, as for a handle's cut.
void cut_open_parts(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                    const PrepareOptions& options) {
  if (options.method != PrepareMethod::kAuto || !options.double_open_sheets ||
      prepared.topology.boundary_edges == 0)
    return;
  WeldResult& welded = prepared.welded;
  if (!input_faces_lead(input, welded)) return;
  StopCheck stop(&options.should_stop);
  const OpenPartCuts cuts = cut_open_parts_into_discs(welded.mesh, &stop);
  if (cuts.parts_cut == 0) return;
  prepared.preparation.open_parts_cut = cuts.parts_cut;
  copy_cut_input_vertices(input, look, welded);
  prepared.topology = analyze_topology(welded.mesh, &stop);
}

// Non-manifold vertices split into one vertex per fan (vertex_split.h), on the welded mesh
// (a weld would merge the copies again); the input's vertices there follow.
void split_pinched_vertices(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                            const PrepareOptions& options) {
  if (prepared.topology.non_manifold_vertices == 0) return;
  WeldResult& welded = prepared.welded;
  if (!input_faces_lead(input, welded)) return;
  StopCheck stop(&options.should_stop);
  const VertexSplit split = split_non_manifold_vertices(welded.mesh, &stop);
  prepared.preparation.vertices_split = split.vertices_split;
  if (split.vertices_added == 0) return;
  copy_cut_input_vertices(input, look, welded);
  prepared.topology = analyze_topology(welded.mesh, &stop);
}

// Non-manifold edges where closed surfaces meet split between them (edge_split.h), on the
// welded mesh; the input's vertices there follow, as for pinched vertices. Returns the
// faces added (interior walls' copies).
size_t split_shared_edges(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                          const PrepareOptions& options) {
  size_t wall_faces = 0;
  if (prepared.topology.non_manifold_edges == 0) return wall_faces;
  WeldResult& welded = prepared.welded;
  if (!input_faces_lead(input, welded)) return wall_faces;
  StopCheck stop(&options.should_stop);
  const EdgeSplit split = split_non_manifold_edges(welded.mesh, &stop);
  prepared.preparation.edges_split = split.edges_split;
  if (split.vertices_added > 0) prepared.topology = analyze_topology(welded.mesh, &stop);
  size_t added = split.vertices_added;
  // Walls two solids share, stored once: doubled, one side each.
  if (prepared.topology.non_manifold_edges > 0) {
    const size_t before = prepared.topology.non_manifold_edges;
    const InteriorWalls walls = double_interior_walls(welded.mesh, &stop);
    if (walls.walls > 0) {
      added += walls.vertices_added;
      prepared.preparation.walls_doubled = walls.walls;
      wall_faces = walls.faces_added;
      prepared.topology = analyze_topology(welded.mesh, &stop);
      prepared.preparation.edges_split +=
          before - std::min(before, prepared.topology.non_manifold_edges);
    }
  }
  // Each split below is made per vertex, the faces at some edges paired (vertex_split.h).
  auto split_paired = [&](const EdgePairs& pairs) {
    if (pairs.empty()) return;
    const size_t before = prepared.topology.non_manifold_edges;
    const VertexSplit split = split_non_manifold_vertices(welded.mesh, &stop, &pairs);
    added += split.vertices_added;
    if (split.vertices_added == 0) return;
    prepared.topology = analyze_topology(welded.mesh, &stop);
    prepared.preparation.edges_split += before - prepared.topology.non_manifold_edges;
  };
  // Edges where one surface touches itself: faces paired by angle; an edge of four faces
  // left joined is tried again with the other match.
  for (const bool other : {false, true})
    if (prepared.topology.non_manifold_edges > 0)
      split_paired(pair_faces_at_non_manifold_edges(welded.mesh, other, &stop));
  // Sheets that end on a surface passing through the edge (a wall on a floor): let go.
  if (prepared.topology.non_manifold_edges > 0)
    split_paired(pair_sheets_ending_on_edges(welded.mesh, &stop));
  // Any edge still shared by more: what pairs by angle kept, the rest let go.
  if (prepared.topology.non_manifold_edges > 0)
    split_paired(pair_faces_letting_go_of_the_rest(welded.mesh, &stop));
  if (added > 0) copy_cut_input_vertices(input, look, welded);
  return wall_faces;
}

// Whether clean_faces would change nothing, from the weld's topology alone: triangles
// only, closed, every edge of two faces running opposite ways, no corner twice, and no part
// of 2 faces. Then no face collapses or shortens (a corner twice), no T-junction has a
// crack to zip (a boundary), no part is misoriented, and no two triangles share their
// corners (they would be a part of their own, of 2 faces). A kit of 1,024 closed parts
// (6M triangles) spent 4 of its 11 s of preparation learning that.
bool nothing_to_clean(const PreparedMesh& as_given, const PrepareOptions& options) {
  const TopologyReport& t = as_given.topology;
  return !options.largest_component && t.face_sizes.size() == 1 && t.face_sizes.count(3) &&
         t.boundary_edges == 0 && t.non_manifold_edges == 0 && t.inconsistent_edges == 0 &&
         t.faces_with_repeated_vertices == 0 &&
         std::all_of(t.component_faces.begin(), t.component_faces.end(),
                     [](size_t faces) { return faces > 2; });
}

PreparedMesh prepare_once(PolygonMesh& input, GltfAppearance* look, const PrepareOptions& options) {
  PreparedMesh as_given = prepare_mesh(input, options);
  // A mesh that maps as it is has nothing to clean (a duplicate face, a collapsed one or a
  // flipped one each fails a check), so repair costs nothing there.
  if (options.method == PrepareMethod::kExact || mapping_failures(as_given.topology).empty()) {
    as_given.preparation.method = options.method;
    as_given.preparation.weld_tolerance = options.weld_tolerance;
    return as_given;
  }
  StopCheck stop(&options.should_stop);
  FaceCleanup cleanup = nothing_to_clean(as_given, options)
                            ? FaceCleanup{}
                            : clean_faces(input, options.weld_tolerance, &stop);
  const size_t input_faces = input.face_count();
  PreparedMesh prepared;
  if (cleanup.changed()) {
    input = std::move(cleanup.mesh);
    if (look) move_face_ranges(*look, cleanup.source_face);
    prepared = prepare_mesh(input, options);
    prepared.input_topology = std::move(as_given.input_topology);
  } else {  // nothing safe to clean: the input as given, already prepared
    prepared = std::move(as_given);
  }
  PreparationReport& report = prepared.preparation;
  report.method = options.method;
  report.weld_tolerance = options.weld_tolerance;
  report.input_faces = input_faces;
  report.collapsed_faces = cleanup.collapsed_faces;
  report.shortened_faces = cleanup.shortened_faces;
  report.duplicate_faces = cleanup.duplicate_faces;
  report.flipped_faces = cleanup.flipped_faces;
  report.reoriented_parts = cleanup.reoriented_parts;
  report.t_junctions_zipped = cleanup.t_junctions_zipped;
  const size_t wall_faces = split_shared_edges(prepared, input, look, options);
  split_pinched_vertices(prepared, input, look, options);
  const size_t own_faces = prepared.welded.mesh.face_count();
  const size_t kept_open = fill_small_holes(prepared, options);
  report.faces_added += wall_faces;  // (the fill's count is set, not added)
  close_short_handles(prepared, input, look, options, own_faces);
  const size_t closed_faces = prepared.welded.mesh.face_count();
  cut_open_parts(prepared, input, look, options);
  double_open_sheets(prepared, options);
  // A hole left open for its part's back where the part could not have one (a back
  // triangle of no area, a cut that failed) is filled after all.
  const size_t doubled_faces = prepared.welded.mesh.face_count();
  if (kept_open > 0 && prepared.topology.boundary_edges > 0) {
    PrepareOptions fill_only = options;
    fill_only.double_open_sheets = false;
    const PreparationReport before = report;
    fill_small_holes(prepared, fill_only);
    report.holes_filled += before.holes_filled;
    report.vertices_added += before.vertices_added;
    report.faces_added += before.faces_added;
    report.largest_fill = std::max(report.largest_fill, before.largest_fill);
  }
  // Fills are triangles appended after the mesh's own faces (a cut may have renamed their
  // corners since, so they are read at the end). A sheet's back is no fill: it is the
  // input's surface again, weighed alike (squeezed, it left the sheet's corners few samples
  // of the remesh), its distortion that of a map of the input.
  const PolygonMesh& mesh = prepared.welded.mesh;
  for (size_t f = own_faces; f < mesh.face_count(); ++f)
    if (mesh.face_size(f) == 3 && (f < closed_faces || f >= doubled_faces))
      prepared.filled.push_back({mesh.face(f)[0], mesh.face(f)[1], mesh.face(f)[2]});
  return prepared;
}

// The bounding-box diagonal of `mesh` (0 when it has no vertex).
double diagonal_of(const PolygonMesh& mesh) {
  if (mesh.positions.empty()) return 0;
  Vec3 low = mesh.positions.front(), high = low;
  for (const Vec3& p : mesh.positions) {
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  return norm(high - low);
}

// The envelope options of one part of an asset under kAuto: the asset's voxel size and
// offset (so a small part gets a small grid, and every part the same offset), at least 16
// voxels across the part grown by the offset, and about twice the part's faces (256 to
// 20,000). Nothing for a part of no extent. The 16 count across the grown part, not the
// part alone: a stray triangle a hundredth of a voxel wide got voxels that small while its
// offset stayed the asset's, so its grid held 400^3 voxels of a ball of the offset's radius
// (a robot hand of 8,339 triangles took 40 s, 15 such triangles; reach set 5).
std::optional<EnvelopeOptions> part_envelope_options(const PolygonMesh& part, double asset_diagonal,
                                                     const PrepareOptions& options) {
  EnvelopeOptions wrap = options.envelope;
  const double diagonal = diagonal_of(part);
  if (!(diagonal > 0) || !(asset_diagonal > 0)) return std::nullopt;
  const double voxel = asset_diagonal / wrap.resolution;
  if (wrap.offset <= 0)
    wrap.offset = wrap.offset_fraction > 0 ? wrap.offset_fraction * asset_diagonal
                                           : wrap.offset_voxels * voxel;
  const double grown = diagonal + 2 * wrap.offset;
  wrap.resolution = std::max(16.0 * diagonal / grown, diagonal / voxel);
  if (wrap.target_faces == 0)
    wrap.target_faces = std::clamp<size_t>(2 * part.face_count(), 256, 20000);
  return wrap;
}

// Whether the repair changed the part's surface: faces added (hole fills, handle caps) or
// dropped (collapsed, duplicate). Vertex copies and flips do not move it.
bool part_was_changed(const PolygonMesh& part, const PolygonMesh& input,
                      const std::vector<uint32_t>& original_faces) {
  size_t corners = 0;
  for (uint32_t f : original_faces) corners += input.face_size(f);
  size_t part_corners = 0;
  for (size_t f = 0; f < part.face_count(); ++f) part_corners += part.face_size(f);
  return part.face_count() != original_faces.size() || part_corners != corners;
}

// `report`'s distances measured again between `envelope` and `original` (as build_envelope
// measures them: core/mesh/surface_distance, the RMS over the vertices of both), relative to
// the asset's diagonal as part_envelope leaves them.
void measure_to_original(EnvelopeReport& report, const PolygonMesh& envelope,
                         const PolygonMesh& original, double asset_diagonal,
                         const PrepareOptions& options) {
  std::vector<Triangle> triangles;
  for (const Triangle& t : fan_triangulate(original).triangles)
    if (is_finite(original.positions[t[0]]) && is_finite(original.positions[t[1]]) &&
        is_finite(original.positions[t[2]]))
      triangles.push_back(t);
  std::vector<Triangle> envelope_triangles(envelope.face_count());
  for (size_t f = 0; f < envelope_triangles.size(); ++f) {
    const auto c = envelope.face(f);
    envelope_triangles[f] = {c[0], c[1], c[2]};
  }
  const std::function<bool()> stop = envelope_stop(options);
  const SurfaceDistance d =
      surface_distance(original.positions, triangles, envelope.positions, envelope_triangles,
                       options.envelope.threads, &stop, DistanceSamples::kVertices);
  const double scale = d.diagonal / asset_diagonal;
  report.hausdorff = d.hausdorff * scale;
  report.rms = d.rms * scale;
  report.envelope_to_original = d.max_b_to_a * scale;
  report.original_to_envelope = d.max_a_to_b * scale;
}

// The envelope of one part of an asset under kAuto, with part_envelope_options. Nothing
// when it cannot be made (a part of no extent, a grid over the cap): the part is then left
// out as it was. Without `measure_distance` its distances are left to the caller.
std::optional<Envelope> part_envelope(const PolygonMesh& part, double asset_diagonal,
                                      const PrepareOptions& options, bool measure_distance) {
  std::optional<EnvelopeOptions> options_of_part =
      part_envelope_options(part, asset_diagonal, options);
  if (!options_of_part) return std::nullopt;
  options_of_part->measure_distance = measure_distance;
  const EnvelopeOptions& wrap = *options_of_part;
  try {
    const std::function<bool()> stop = envelope_stop(options);
    Envelope envelope = build_envelope(part, wrap, &stop);
    // Distances relative to the asset's diagonal, as every other figure of the asset.
    EnvelopeReport& r = envelope.report;
    const double scale = r.diagonal / asset_diagonal;
    for (double* relative :
         {&r.hausdorff, &r.rms, &r.envelope_to_original, &r.original_to_envelope})
      *relative *= scale;
    r.diagonal = asset_diagonal;
    return envelope;
  } catch (const InputError& e) {
    if (e.check() == "stopped") throw;
    return std::nullopt;
  }
}

// Under kAuto, each part that does not map (keep[k] false) replaced by its envelope, which
// then maps in its place; a part no envelope can be made of stays left out.
void wrap_left_out_parts(PreparedMesh& prepared, const PolygonMesh& input,
                         std::vector<MeshPart>& parts, std::vector<char>& keep,
                         const PrepareOptions& options) {
  const WeldResult& welded = prepared.welded;
  const double asset_diagonal = diagonal_of(welded.mesh);
  // Per welded vertex its part, so each input face finds its part (by its first corner).
  std::vector<uint32_t> part_of(welded.mesh.vertex_count(), kUnreferenced);
  for (size_t k = 0; k < parts.size(); ++k)
    for (uint32_t v : parts[k].vertex) part_of[v] = static_cast<uint32_t>(k);
  auto faces_of_part = [&](size_t k) {
    std::vector<uint32_t> faces;
    for (size_t f = 0; f < input.face_count(); ++f) {
      const uint32_t w = welded.input_to_welded[input.face(f)[0]];
      if (w != kUnreferenced && part_of[w] == k) faces.push_back(static_cast<uint32_t>(f));
    }
    return faces;
  };
  for (size_t k = 0; k < parts.size(); ++k) {
    if (keep[k]) continue;
    std::vector<uint32_t> original_faces = faces_of_part(k);
    // The envelope is of the part as repaired (its fills are closer caps than the grid's:
    // beetle.obj 4.6% of the diagonal, 5.4% when wrapped without them), but its distances
    // are measured to the part's own input faces, which the outputs stand for: a fill
    // inside the envelope hid how far it is from them (lato315.ply: 1.4% said, 4.5% true).
    // Then they are measured once, here, not also to the repaired part.
    const bool changed = part_was_changed(parts[k].mesh, input, original_faces);
    std::optional<Envelope> envelope =
        part_envelope(parts[k].mesh, asset_diagonal, options, !changed);
    if (!envelope) continue;
    if (changed)
      measure_to_original(envelope->report, envelope->mesh, submesh(input, original_faces).mesh,
                          asset_diagonal, options);
    PartReport& report = prepared.parts[k];
    report.wrapped = true;
    report.wrap_reasons = std::move(report.failures);
    report.failures.clear();
    report.envelope = envelope->report;
    report.original_faces = std::move(original_faces);
    parts[k].mesh = std::move(envelope->mesh);
    parts[k].vertex.assign(parts[k].mesh.vertex_count(), kUnreferenced);  // no input vertex
    keep[k] = true;
  }
}

// Under kParts and kAuto, `welded` cut down to the parts kept (keep[k]) when some part maps
// (the others' input vertices then weld to nothing).
void cut_to_kept_parts(PreparedMesh& prepared, std::vector<MeshPart>& parts,
                       const std::vector<char>& keep, const PrepareOptions& options) {
  StopCheck stop(&options.should_stop);
  WeldResult& welded = prepared.welded;
  if (!maps_by_parts(options.method) || prepared.parts_left_out() == parts.size()) return;
  const bool wrapped = std::any_of(prepared.parts.begin(), prepared.parts.end(),
                                   [](const PartReport& p) { return p.wrapped; });
  if (prepared.parts_left_out() == 0 && !wrapped) {
    for (size_t k = 0; k < parts.size(); ++k) prepared.parts[k].welded_vertex = parts[k].vertex[0];
    return;  // nothing to drop: `welded` stays as it is
  }
  // The kept parts one after the other, in the order of the parts (largest first).
  PolygonMesh kept;
  std::vector<uint32_t> new_id(welded.mesh.vertex_count(), kUnreferenced);
  std::vector<uint32_t> corners;
  for (size_t k = 0; k < parts.size(); ++k) {
    if (!keep[k]) continue;
    const MeshPart& part = parts[k];
    const uint32_t first = static_cast<uint32_t>(kept.positions.size());
    prepared.parts[k].welded_vertex = first;
    for (size_t v = 0; v < part.vertex.size(); ++v) {
      if (part.vertex[v] != kUnreferenced)
        new_id[part.vertex[v]] = first + static_cast<uint32_t>(v);
      kept.positions.push_back(part.mesh.positions[v]);
    }
    for (size_t f = 0; f < part.mesh.face_count(); ++f) {
      corners.clear();
      for (uint32_t v : part.mesh.face(f)) corners.push_back(first + v);
      kept.add_face(corners);
    }
  }
  for (uint32_t& w : welded.input_to_welded)
    if (w != kUnreferenced) w = new_id[w];
  rename_triangles(prepared.filled, new_id);
  welded.mesh = std::move(kept);
  prepared.topology = analyze_topology(welded.mesh, &stop);
}

// An asset of several parts: each part checked alone (under any method, so a refusal can
// say what "parts" would do), and under kParts `welded` cut down to the parts that map when
// some do (the others' input vertices then weld to nothing). Under kAuto each part that
// does not map is replaced by its envelope instead of being left out (under
// defer_envelopes, left to build_envelopes with `welded` uncut).
void keep_mappable_parts(PreparedMesh& prepared, const PolygonMesh& input,
                         const PrepareOptions& options) {
  if (options.largest_component || prepared.topology.component_vertices.size() < 2) return;
  StopCheck stop(&options.should_stop);
  WeldResult& welded = prepared.welded;
  std::vector<MeshPart> parts = connected_parts(welded.mesh, &stop);
  std::vector<char> keep(parts.size());
  for (size_t k = 0; k < parts.size(); ++k) {
    PartReport report;
    report.vertices = parts[k].mesh.vertex_count();
    report.faces = parts[k].mesh.face_count();
    report.failures = mapping_failures(analyze_topology(parts[k].mesh, &stop));
    for (ValidationFailure& f : report.failures)
      if (f.check == "genus")
        for (const HandleClosing::Stopped& stopped : prepared.handle_stops)
          if (std::find(parts[k].vertex.begin(), parts[k].vertex.end(), stopped.vertex) !=
              parts[k].vertex.end())
            f.message += "; closing its handles stopped: " + stopped.reason;
    keep[k] = report.mappable();
    prepared.parts.push_back(std::move(report));
  }
  // Past kMaxWrappedParts the parts are wrapped as one (prepare_input).
  if (options.method == PrepareMethod::kAuto && prepared.parts_left_out() <= kMaxWrappedParts) {
    if (options.defer_envelopes && prepared.parts_left_out() > 0) {
      prepared.pending.parts = true;
      return;
    }
    wrap_left_out_parts(prepared, input, parts, keep, options);
  }
  cut_to_kept_parts(prepared, parts, keep, options);
}

// prepare_once, then the parts step.
PreparedMesh prepare_parts(PolygonMesh& input, GltfAppearance* look,
                           const PrepareOptions& options) {
  PreparedMesh prepared = prepare_once(input, look, options);
  if (!mapping_failures(prepared.topology).empty()) keep_mappable_parts(prepared, input, options);
  return prepared;
}

// Whether every part of the input maps (none left out, nothing else in the way).
bool maps_entirely(const PreparedMesh& prepared) {
  return prepared.parts_left_out() == 0 && remaining_failures(prepared).empty();
}

// The weld tolerances worth trying on `input`, smallest first: none when the widest welds
// no more than exact positions do.
std::vector<double> weld_tolerances_to_try(const PolygonMesh& input,
                                           const PrepareOptions& options) {
  StopCheck stop(&options.should_stop);
  if (weld(input, 1e-4, &stop).mesh.vertex_count() == weld(input, 0, &stop).mesh.vertex_count())
    return {};
  return {1e-6, 1e-5, 1e-4};
}

// The smallest of a few weld tolerances with which `input` maps, 0 when none does. Each
// try is one more weld and topology pass over a copy (linear, like preparing itself).
double closing_weld_tolerance(const PolygonMesh& input, PrepareOptions options) {
  for (const double tolerance : weld_tolerances_to_try(input, options)) {
    options.weld_tolerance = tolerance;
    PolygonMesh copy = input;
    if (maps_entirely(prepare_parts(copy, nullptr, options))) return tolerance;
  }
  return 0;
}

// The max_hole_fill with which `input` maps when every hole left was left for its size:
// the largest such fill's share rounded up to two digits (at most 1), tried; 0 otherwise.
double closing_hole_fill(const PolygonMesh& input, const PreparationReport& report,
                         PrepareOptions options) {
  if (report.holes_too_large == 0 || report.holes_too_large != report.holes_left) return 0;
  const double share = report.largest_left_fill;
  const double step = std::pow(10.0, std::floor(std::log10(share)) - 1);
  const double value = std::ceil(share / step - 1e-9) * step;
  if (!(value > options.max_hole_fill) || value > 1) return 0;
  options.max_hole_fill = value;
  PolygonMesh copy = input;
  return maps_entirely(prepare_parts(copy, nullptr, options)) ? value : 0;
}

// When the failures offer largest_component, it is tried on the input as prepared (the
// same method: cleaned, split, filled and closed as it would be) so the hint says what
// the largest part fails then, not before those steps.
void try_largest_component(PreparedMesh& prepared, const PolygonMesh& input,
                           PrepareOptions options) {
  // Two parts or more that map: the refusal offers prepare=parts instead (input_failures).
  const size_t parts_that_map = prepared.parts.size() - prepared.parts_left_out();
  if (options.largest_component || parts_that_map >= 2) return;
  const std::vector<ValidationFailure> failures = remaining_failures(prepared);
  if (std::none_of(failures.begin(), failures.end(),
                   [](const ValidationFailure& f) { return f.fix.option == "largest_component"; }))
    return;
  options.largest_component = true;
  PolygonMesh copy = input;
  const PreparedMesh largest = prepare_parts(copy, nullptr, options);
  prepared.largest_component_failures = remaining_failures(largest);
  prepared.largest_component_faces = largest.welded.mesh.face_count();
}

// What kAuto did, for preparation.decided.
std::string decided(const PreparedMesh& prepared) {
  if (std::any_of(prepared.parts.begin(), prepared.parts.end(),
                  [](const PartReport& p) { return p.wrapped; }))
    return "parts+wrap";
  if (!prepared.parts.empty()) return "parts";
  const PreparationReport& r = prepared.preparation;
  // A vertex split moves nothing but the mesh mapped is no longer the file's own (a
  // non-manifold edge or vertex became two): said as a repair, not as exact.
  const bool changed = r.collapsed_faces || r.shortened_faces || r.duplicate_faces ||
                       r.t_junctions_zipped || r.flipped_faces || r.faces_added ||
                       r.vertices_split || r.edges_split || r.weld_tolerance > 0;
  return changed ? "repair" : "exact";
}

// The input's own topology, for the report's "input" (topology_json): the weld and the
// report alone, no largest-part check of a soup.
TopologyReport topology_as_read(const PolygonMesh& input, const PrepareOptions& options) {
  StopCheck stop(&options.should_stop);
  return analyze_topology(weld(input, options.weld_tolerance, &stop).mesh, &stop);
}

// The whole input replaced by its envelope; the input and its look moved to `original`.
// Throws (and leaves both as they were) when the envelope cannot be made.
// `as_read`: the input's own topology as the caller reports it (the input may have been
// cleaned since; topology_as_read), kept as input_topology; none where nobody reads it (the
// worker's build_envelopes).
PreparedMesh wrap_whole(PolygonMesh& input, GltfAppearance* look, const PrepareOptions& options,
                        std::optional<TopologyReport> as_read) {
  const std::function<bool()> stop = envelope_stop(options);
  Envelope envelope = build_envelope(input, options.envelope, &stop);
  const size_t input_faces = input.face_count();
  auto original = std::make_shared<WrappedOriginal>();
  original->mesh = std::move(input);
  if (look) {
    original->look = std::move(*look);
    *look = GltfAppearance{};
  }
  input = std::move(envelope.mesh);
  PreparedMesh prepared = prepare_mesh(input, options);
  prepared.original = std::move(original);
  prepared.preparation.method = PrepareMethod::kWrap;
  prepared.preparation.input_faces = input_faces;
  prepared.preparation.envelope = envelope.report;
  prepared.input_topology = std::move(as_read);
  return prepared;
}

// Under defer_envelopes, when the whole's grid is over the cap: whether every part that does
// not map has an envelope grid within it (counted, nothing allocated).
bool every_left_out_part_fits(const PreparedMesh& prepared, const PrepareOptions& options) {
  StopCheck stop(&options.should_stop);
  const std::vector<MeshPart> parts = connected_parts(prepared.welded.mesh, &stop);
  if (parts.size() != prepared.parts.size()) return false;
  const double asset_diagonal = diagonal_of(prepared.welded.mesh);
  for (size_t k = 0; k < parts.size(); ++k) {
    if (prepared.parts[k].mappable()) continue;
    const std::optional<EnvelopeOptions> wrap =
        part_envelope_options(parts[k].mesh, asset_diagonal, options);
    if (!wrap) return false;
    try {
      plan_envelope(parts[k].mesh, *wrap);
    } catch (const InputError&) {
      return false;
    }
  }
  return true;
}

// Under defer_envelopes: what build_envelopes needs, once the whole's grid is known to
// fit. Throws build_envelope's InputError when it does not.
PendingEnvelopes pending_envelopes(const PolygonMesh& input, const PrepareOptions& options) {
  PendingEnvelopes pending;
  pending.method = options.method;
  pending.envelope = options.envelope;
  pending.weld_tolerance = options.weld_tolerance;
  pending.grid_voxels = plan_envelope(input, options.envelope).grid.size();
  return pending;
}

// Whether the prepared input, or one of its parts, failed for a boundary (still, or before
// it was wrapped).
bool has_boundary(const PreparedMesh& prepared) {
  bool boundary = prepared.topology.boundary_edges > 0;
  for (const PartReport& part : prepared.parts) {
    for (const ValidationFailure& f : part.failures) boundary |= f.check == "boundary";
    for (const ValidationFailure& f : part.wrap_reasons) boundary |= f.check == "boundary";
  }
  return boundary;
}

// Whether some part was closed by its own back (an open sheet, a cut, an opened handle).
bool has_backs(const PreparationReport& report) {
  return report.sheets_doubled > 0 || report.open_parts_cut > 0 || report.handles_opened > 0;
}

bool wraps_a_part(const PreparedMesh& prepared) {
  return prepared.pending.parts || std::any_of(prepared.parts.begin(), prepared.parts.end(),
                                               [](const PartReport& p) { return p.wrapped; });
}

// Under kAuto, before any part is wrapped: the input welded at the smallest of
// closing_weld_tolerance's tolerances with which every part maps, when one does (a CAD
// export's seam vertices a float apart), prepared so; nothing otherwise. A weld moves
// a point by at most that share of the diagonal (1e-6 to 1e-4), an envelope by its offset.
//
// `with_backs`: the input mapped, nothing wrapped, but some part closed by its own back (a
// seam a float apart left open is a hole, which a back closes at half the remesh's samples
// per side: iCub's and the allegro hand's CAD parts). A weld is then taken only when it
// closes every hole by itself: the trial has neither backs nor fills.
std::optional<PreparedMesh> closed_by_weld(PolygonMesh& input, GltfAppearance* look,
                                           const PreparedMesh& prepared,
                                           const PrepareOptions& options, bool with_backs) {
  const bool read_open = prepared.input_topology && prepared.input_topology->boundary_edges > 0;
  if (options.weld_tolerance != 0 || !(has_boundary(prepared) || (with_backs && read_open)))
    return std::nullopt;
  PrepareOptions trial = options;
  trial.defer_envelopes = true;  // a trial maps entirely only with no part left to wrap
  if (with_backs) trial.double_open_sheets = false, trial.max_hole_fill = 0;
  // The preparation at `tolerance` under `with`, on copies (`prepared` stands for the input
  // as it is unless one maps).
  struct Welded {
    PolygonMesh input;
    std::optional<GltfAppearance> look;
    PreparedMesh prepared;
    bool taken = false;  // maps, nothing wrapped
  };
  const auto prepare_at = [&](double tolerance, const PrepareOptions& with) {
    PrepareOptions welded = with;
    welded.weld_tolerance = tolerance;
    Welded out{input, std::nullopt, {}};
    if (look) out.look = *look;
    out.prepared = prepare_parts(out.input, out.look ? &*out.look : nullptr, welded);
    out.taken = maps_entirely(out.prepared) && !wraps_a_part(out.prepared);
    return out;
  };
  const auto take = [&](Welded& welded) {
    input = std::move(welded.input);
    if (look) *look = std::move(*welded.look);
    welded.prepared.input_topology = prepared.input_topology;
    welded.prepared.preparation.decided = decided(welded.prepared);
    return std::move(welded.prepared);
  };
  for (const double tolerance : weld_tolerances_to_try(input, trial)) {
    Welded tried = prepare_at(tolerance, trial);
    if (!tried.taken) continue;
    // The trial is the preparation itself where it differs from it in nothing that ran:
    // deferring envelopes changes nothing where every part maps, and without backs a trial
    // that maps had no hole to fill or close by a back, nor a handle cap far enough to be
    // opened for one. Kept, not made again (carbon-sphere.glb: 14 s of handle closing).
    if (!with_backs || tried.prepared.preparation.farthest_handle_fill <= kFarHoleFill)
      return take(tried);
    Welded real = prepare_at(tolerance, options);
    if (!real.taken) return std::nullopt;
    return take(real);
  }
  return std::nullopt;
}

}  // namespace

PreparedMesh prepare_input(PolygonMesh& input, GltfAppearance* look,
                           const PrepareOptions& options) {
  if (options.method == PrepareMethod::kAuto) {
    // Every part that maps as it is (after the safe cleaning), each other part wrapped; a
    // mesh the preparation shattered, wrapped whole.
    PreparedMesh prepared = prepare_parts(input, look, options);
    const bool shards = shattered(prepared);
    if (shards) prepared.pending.parts = false;
    const bool mapped = !shards && (maps_entirely(prepared) || options.largest_component);
    const bool unwrapped = !prepared.pending.parts && mapped && !wraps_a_part(prepared);
    if (unwrapped && !has_backs(prepared.preparation)) {
      prepared.preparation.decided = decided(prepared);
      return prepared;
    }
    if (std::optional<PreparedMesh> closed =
            shards ? std::nullopt : closed_by_weld(input, look, prepared, options, unwrapped))
      return std::move(*closed);
    if (unwrapped) {  // with backs that no weld closes
      prepared.preparation.decided = decided(prepared);
      return prepared;
    }
    if (!prepared.pending.parts && mapped) {  // some parts wrapped
      prepared.preparation.decided = decided(prepared);
      return prepared;
    }
    if (options.defer_envelopes) {
      const bool parts = prepared.pending.parts;
      try {
        prepared.pending = pending_envelopes(input, options);
      } catch (const InputError&) {
        // No envelope of the whole: the parts' may still do (their grids are smaller);
        // without them the refusal says what the parts fail, as below. A part whose own
        // grid is over the cap too would stay out, and the job would then fail in its
        // worker: refused here instead, as the eager path refuses it.
        if (!parts || !every_left_out_part_fits(prepared, options)) {
          prepared.pending = {};
          return prepared;
        }
        prepared.pending.method = PrepareMethod::kAuto;
        prepared.pending.envelope = options.envelope;
        prepared.pending.weld_tolerance = options.weld_tolerance;
        prepared.pending.grid_voxels = options.envelope.max_voxels;
      }
      prepared.pending.parts = parts;
      return prepared;
    }
    // One part that does not map (or parts no envelope could be made of): the whole
    // asset's envelope. When even that cannot be made, the refusal says what the parts fail.
    try {
      PreparedMesh wrapped = wrap_whole(input, look, options, prepared.input_topology);
      wrapped.preparation.method = PrepareMethod::kAuto;
      wrapped.preparation.decided = "wrap";
      return wrapped;
    } catch (const InputError& e) {
      if (e.check() == "stopped") throw;
      return prepared;
    }
  }
  if (options.method == PrepareMethod::kWrap) {
    if (!options.defer_envelopes)
      return wrap_whole(input, look, options, topology_as_read(input, options));
    // Nothing is welded here: the worker prepares the envelope (wrap_whole).
    PreparedMesh prepared;
    prepared.preparation.method = PrepareMethod::kWrap;
    prepared.preparation.input_faces = input.face_count();
    prepared.pending = pending_envelopes(input, options);
    return prepared;
  }
  PreparedMesh prepared = prepare_parts(input, look, options);
  try_largest_component(prepared, input, options);
  const bool boundary = has_boundary(prepared);
  // Tried on the input as cleaned: cleaning again at the wider tolerance drops what that
  // weld collapses, as it would on the original.
  if (options.weld_tolerance == 0 && boundary && !maps_entirely(prepared))
    prepared.closing_weld_tolerance = closing_weld_tolerance(input, options);
  if (boundary && prepared.closing_weld_tolerance == 0 && !maps_entirely(prepared))
    prepared.closing_hole_fill = closing_hole_fill(input, prepared.preparation, options);
  return prepared;
}

void build_envelopes(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                     const std::function<bool()>& should_stop) {
  const PendingEnvelopes pending = prepared.pending;
  if (!pending.any()) return;
  PrepareOptions options;
  options.method = pending.method;
  options.envelope = pending.envelope;
  options.weld_tolerance = pending.weld_tolerance;
  options.should_stop = should_stop;
  prepared.pending = {};
  if (pending.method == PrepareMethod::kWrap) {
    // No input topology: the job's results do not report it (only info and the intake's
    // 422 do, and the intake refuses nothing it leaves to the worker).
    prepared = wrap_whole(input, look, options, std::nullopt);
    return;
  }
  if (pending.parts) {
    // The parts as prepare_input found them: the same welded mesh gives the same parts, in
    // the same order as prepared.parts.
    StopCheck stop(&options.should_stop);
    std::vector<MeshPart> parts = connected_parts(prepared.welded.mesh, &stop);
    if (parts.size() != prepared.parts.size())
      throw InputError("internal", "the parts to wrap are not the parts that were checked");
    std::vector<char> keep(parts.size());
    for (size_t k = 0; k < parts.size(); ++k) keep[k] = prepared.parts[k].mappable();
    wrap_left_out_parts(prepared, input, parts, keep, options);
    cut_to_kept_parts(prepared, parts, keep, options);
    if (maps_entirely(prepared)) {
      prepared.preparation.decided = decided(prepared);
      return;
    }
  }
  try {
    PreparedMesh wrapped = wrap_whole(input, look, options, prepared.input_topology);
    wrapped.preparation.method = PrepareMethod::kAuto;
    wrapped.preparation.decided = "wrap";
    prepared = std::move(wrapped);
  } catch (const InputError& e) {
    if (e.check() == "stopped") throw;
    std::string left;
    for (const ValidationFailure& f : remaining_failures(prepared))
      left += (left.empty() ? "" : "; ") + f.message;
    if (left.empty())
      for (const PartReport& part : prepared.parts)
        if (!part.mappable() && left.empty())
          left = "a part of " + std::to_string(part.faces) +
                 " faces: " + part.failures.front().message;
    throw InputError(e.check(), std::string("no envelope could be made of it (") + e.what() + ")" +
                                    (left.empty() ? "" : "; unwrapped, " + left));
  }
}

}  // namespace spheremap
