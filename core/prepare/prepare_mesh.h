// Preparing an input for the map (ALGORITHM §0), between reading (core/io) and mapping
// (core/map): optional cleaning that moves no vertex (face_cleanup.h), the weld, the
// largest part when asked, and the topology report. Nothing here refuses: the map's
// caller checks the report (mapping_failures) and says why.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/io/gltf_appearance.h"
#include "core/mesh/mesh.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/prepare/envelope.h"
#include "core/prepare/handle_closing.h"

namespace spheremap {

// How far preparation may change the input. kExact: as it is (refuse anything not closed
// genus 0). kRepair: also the cleaning of face_cleanup.h (a mesh that needs none is
// untouched, so its map is the same as under kExact). kParts (default): also, for an asset
// of several parts (connected components), every part that is closed genus 0 maps on a
// sphere of its own and the others are left out, each listed with its reason. kWrap: the
// input is replaced by its envelope (envelope.h), a closed genus-0 mesh around all of it at
// about the offset, which maps like any mesh; its outputs show the envelope (the sphere in
// the "original" layout is the envelope's), and the input with its look is kept beside
// (PreparedMesh::original) for the outputs to bake and measure against.
// kAuto: the least change that maps every part: as kParts, and then each part that still
// cannot map is replaced by its own envelope (one mesh of one part: the whole is wrapped),
// so every part is served, exactly where it can be. Before any envelope, a part that is a
// disc whose hole is too large to fill is closed by its own back (sheet_doubling.h): exact,
// no vertex moved. preparation.decided says what was done.
enum class PrepareMethod { kExact, kRepair, kParts, kWrap, kAuto };
// "exact", "repair", "parts", "wrap", "auto"
const char* prepare_method_name(PrepareMethod method);
// Whether `method` maps every part that maps on its own (kParts, kAuto).
inline bool maps_by_parts(PrepareMethod method) {
  return method == PrepareMethod::kParts || method == PrepareMethod::kAuto;
}

struct PrepareOptions {
  PrepareMethod method = PrepareMethod::kParts;
  double weld_tolerance = 0;  // relative to the bounding-box diagonal; 0 = exact positions
  // Keep only the connected component with the most faces (others are dropped, their
  // input vertices then map to nothing); otherwise several components are an error.
  bool largest_component = false;
  // repair and parts: holes whose least-area fill is at most this share of the surface
  // area are closed (hole_filling.h); 0: none.
  double max_hole_fill = 0.05;
  // Hole fills refined and faired (Liepa 2003; fill_refinement.h): new vertices inside each
  // fill so a wide hole's cap continues the surface; false: the least-area fill alone.
  bool refine_hole_fills = true;
  // repair and parts: handles of closed, manifold, oriented parts are closed along
  // non-separating cycles of at most this length over the part's bounding-box diagonal,
  // the shortest whose fill stays near the part first (handle_closing.h); 0: none. 1.5: the longest
  // cycle the reach set's genus > 0 assets need is 1.39 (a printer bed), and every one of them maps
  // certified.
  double max_handle_cycle = 1.5;
  // kAuto: a part that is a disc whose hole is too large to fill is closed by its own back
  // (sheet_doubling.h) rather than wrapped. false: wrapped (tests of the envelope's path).
  bool double_open_sheets = true;
  EnvelopeOptions envelope;  // kWrap only
  // Asked while cleaning, welding and checking: true stops with InputError("stopped")
  // (see StopCheck).
  std::function<bool()> should_stop;
  // Asked, besides should_stop, only while envelopes are built (kWrap, kAuto): the CLI's
  // --time-limit, which must not stop the exact path (a limit that passed there still
  // writes the map reached) but must stop an envelope that would take longer.
  std::function<bool()> envelope_should_stop;
  // Leave every envelope (kWrap, kAuto) to build_envelopes: prepare_input does the rest,
  // checks that the whole's envelope grid fits (or refuses as build_envelope would) and
  // says what is left in PreparedMesh::pending. The server's intake does this, so that an
  // envelope's seconds and memory are spent in the job's worker, under its time limit and
  // memory budget, not in the intake threads every submission waits for.
  bool defer_envelopes = false;
};

// What prepare_input left to build_envelopes (PrepareOptions::defer_envelopes).
struct PendingEnvelopes {
  // kWrap: the whole input's envelope. kAuto: first each part that does not map (when
  // `parts`), then, when something still does not map, the whole's. kExact: nothing left.
  PrepareMethod method = PrepareMethod::kExact;
  bool parts = false;  // `welded` still holds every part (not cut down to those that map)
  EnvelopeOptions envelope;
  double weld_tolerance = 0;
  // The whole's grid (max_voxels when over it): no envelope of the job is larger.
  size_t grid_voxels = 0;
  bool any() const { return method != PrepareMethod::kExact; }
};

// What preparation did to the input, for the metrics ("preparation").
struct PreparationReport {
  PrepareMethod method = PrepareMethod::kExact;
  // The weld's tolerance (over the diagonal): the option's, or under kAuto the one that
  // closed the input when it mapped no other way but wrapped (closing_weld_tolerance).
  double weld_tolerance = 0;
  size_t input_faces = 0;
  size_t collapsed_faces = 0, shortened_faces = 0, duplicate_faces = 0, flipped_faces = 0;
  size_t reoriented_parts = 0;
  size_t t_junctions_zipped = 0;  // T-junction vertices inserted into cracks' edges
  size_t vertices_split = 0;      // non-manifold vertices made one vertex per fan
  size_t edges_split = 0;         // non-manifold edges shared out between closed surfaces
  size_t walls_doubled = 0;       // walls two solids shared, stored once (interior_walls.h)
  size_t holes_filled = 0, holes_left = 0;
  size_t faces_added = 0;     // by hole fills, handle closings and sheets' backs together
  size_t vertices_added = 0;  // inside hole fills (refinement) and backs, after the input's own
  size_t sheets_doubled = 0;  // kAuto: open discs closed by their own back (sheet_doubling.h)
  size_t open_parts_cut = 0;  // kAuto: parts of several holes cut into discs (open_part_cuts.h)
  double largest_fill = 0;    // the largest fill's area over the surface area
  // Holes left only for their size (over max_hole_fill), and the largest one's fill share.
  size_t holes_too_large = 0;
  double largest_left_fill = 0;
  size_t handles_closed = 0, handles_left = 0;
  // kAuto: handles cut but left open for the part's back, their caps too far (handle_opening.h)
  size_t handles_opened = 0;
  double largest_handle_cycle = 0;  // the longest cycle cut over its part's diagonal
  double farthest_handle_fill = 0;  // how far a cut's fill strays from its part, likewise
  // Why handles were left (the first part stopped, with the numbers); "" when none was.
  std::string handles_stopped;
  EnvelopeReport envelope;  // kWrap, or kAuto when it wrapped the whole input
  // kAuto: what it took: "exact" (nothing to change), "repair" (cleaned, or holes or
  // handles closed), "parts" (several parts, each maps), "parts+wrap" (some parts wrapped),
  // "wrap" (the whole wrapped). Empty under the other methods.
  std::string decided;
};

// One part (connected component) of an asset, checked alone.
struct PartReport {
  size_t vertices = 0, faces = 0;
  std::vector<ValidationFailure> failures;  // empty: the part maps alone
  bool mappable() const { return failures.empty(); }
  // kAuto: the part did not map alone (`wrap_reasons` say why) and was replaced by its
  // envelope, which maps in its place; its input vertices then weld to nothing.
  bool wrapped = false;
  std::vector<ValidationFailure> wrap_reasons;
  EnvelopeReport envelope;
  // Wrapped: the faces of the input (as prepare_input leaves it, with its look) that the
  // envelope stands for, ascending; what the outputs measure and bake against.
  std::vector<uint32_t> original_faces;
  // Under kParts and kAuto, a vertex of the part in `welded` when the part is kept,
  // kUnreferenced when left out: ties the part to its map (map_parts orders parts anew).
  uint32_t welded_vertex = kUnreferenced;
};

// The input an envelope of the whole stands for (kWrap, or kAuto wrapping the whole): the
// input as it was wrapped (after the safe cleaning) with its look, moved here rather than
// copied, shared by every copy of the prepared mesh and read by the outputs.
struct WrappedOriginal {
  PolygonMesh mesh;
  GltfAppearance look;  // empty when none was given
};

struct PreparedMesh {
  WeldResult welded;
  // The whole input wrapped: what it was; null otherwise (then the input is the original,
  // and a wrapped part's faces are PartReport::original_faces).
  std::shared_ptr<const WrappedOriginal> original;
  TopologyReport topology;  // of `welded`: the mesh that is mapped
  // The input's own topology as read (welded at weld_tolerance, before the largest
  // component is kept, and before any cleaning, split, fill, cut or envelope), so that a
  // report says what the file is as well as what was made of it. Empty where nothing was
  // welded (an envelope left to the worker) and after the worker protocol (the intake
  // reports it).
  std::optional<TopologyReport> input_topology;
  PreparationReport preparation;
  // With several components (and largest_component off): what the largest alone fails,
  // empty when it maps; so `largest_component` is offered only where it works. Under
  // prepare_input, when a failure offers it, it is tried with the same options (the largest
  // part cleaned, split, filled and closed), and these say what that gave.
  std::vector<ValidationFailure> largest_component_failures;
  size_t largest_component_faces = 0;
  // For a mesh with boundaries at weld_tolerance 0: the smallest tolerance tried (1e-6,
  // 1e-5, 1e-4 of the diagonal) with which it maps, 0 when none does (T-junction cracks
  // and near-equal seam vertices of CAD exports), so the fix is named only where it works.
  double closing_weld_tolerance = 0;
  // When holes were left only for their size (and no weld closes the surface): the
  // max_hole_fill that fills them (the largest one's share, rounded up), tried with the
  // same options and it then maps; 0 otherwise. So that fix too is named only where it works.
  double closing_hole_fill = 0;
  // With several components (and largest_component off): every part of the asset, largest
  // first (by faces), each with what it fails alone. Under kParts, when some part maps,
  // `welded` holds only the parts that map (the others' input vertices then map to
  // nothing); otherwise the whole as it is. Empty for one component.
  std::vector<PartReport> parts;
  size_t parts_left_out() const;
  // The triangles hole filling and handle closing added (welded ids, kept through the parts
  // step): the map weighs them MapOptions::filled_weight.
  std::vector<Triangle> filled;
  // Parts whose handles were left (a vertex of each, welded ids before the parts step).
  std::vector<HandleClosing::Stopped> handle_stops;
  PendingEnvelopes pending;  // under defer_envelopes: the envelopes still to build
};

// `triangles` in new vertex ids (new_id[old]); those with a corner that has none
// (kUnreferenced, or beyond new_id) are dropped.
void rename_triangles(std::vector<Triangle>& triangles, std::span<const uint32_t> new_id);

// What stands between `prepared` and its map: mapping_failures of its topology, except that
// under kParts several components are fine once every part kept maps alone.
std::vector<ValidationFailure> remaining_failures(const PreparedMesh& prepared);

// Welds and reports; does not clean and does not reject (preparation.method stays exact).
PreparedMesh prepare_mesh(const PolygonMesh& input, const PrepareOptions& options);

// The same after cleaning `input` in place when options.method is kRepair: faces dropped,
// shortened or reversed, and `look` (when given) has its primitives' face ranges moved to
// match, so the input, its look and the prepared mesh agree for every output. Under kWrap,
// `input` becomes the envelope and `look` (when given) is emptied, both moved to the
// result's `original`; InputError when the envelope cannot be made (envelope.h).
PreparedMesh prepare_input(PolygonMesh& input, GltfAppearance* look, const PrepareOptions& options);

// Builds what prepare_input left under defer_envelopes (prepared.pending), so that
// `prepared`, `input` and `look` are what prepare_input would have made without it (but for
// input_topology under kWrap: nothing reads it after the intake, so it is not computed).
// `should_stop` is asked throughout (InputError "stopped"). Throws InputError when no
// envelope can be made: build_envelope's checks ("envelope_size", "envelope_empty",
// "envelope_topology"), under kAuto with what the input, unwrapped, still fails.
void build_envelopes(PreparedMesh& prepared, PolygonMesh& input, GltfAppearance* look,
                     const std::function<bool()>& should_stop);

}  // namespace spheremap
