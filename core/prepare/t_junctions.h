// T-junction cracks (CAD exports): two sides of a seam meshed separately, so one side's
// boundary edge runs past vertices of the other side's boundary that lie on it. Welding
// cannot close such a crack (there is no vertex to weld to); splitting the long edge's
// face at those vertices can, and moves no vertex.
//
// Preconditions: `faces` in welded ids (one vertex per point) over `positions`. Only
// boundary edges (one face) are split, only at boundary vertices within kTJunctionTolerance
// of the bounding-box diagonal of the segment (and farther than that from its ends, which
// a weld would merge), and only when every piece of the split edge then meets exactly one
// other boundary edge (a piece of the other side, or another split edge's piece): the crack
// closes, nothing becomes non-manifold. The work is bounded: boundary vertices are hashed
// in a grid of about the mean boundary edge's length, each edge visits the cells along it,
// and past kMaxZipCellVisits nothing is zipped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

// How far off a boundary edge a vertex may lie and still split it, over the diagonal.
inline constexpr double kTJunctionTolerance = 1e-5;
// Grid cells visited by all edges together before zipping gives up (about a second).
inline constexpr size_t kMaxZipCellVisits = size_t{1} << 26;

// One face's boundary edge face[corner] -> face[corner + 1] split at `inserted` (welded
// ids, in order from face[corner]).
struct EdgeSplit {
  uint32_t face = 0, corner = 0;
  std::vector<uint32_t> inserted;
};

// The splits that zip the cracks of `faces`, by face then corner; empty when none.
std::vector<EdgeSplit> find_t_junctions(const PolygonMesh& faces,
                                        const std::vector<Vec3>& positions,
                                        StopCheck* stop = nullptr);

// `welded_face` (and `input_face`, the same corners in input ids) with `splits` (that
// face's EdgeSplits, by corner) inserted, triangulated as a fan from a corner that lies on
// none of the split edges' lines, appended to `welded_out` and `input_out` (inserted
// corners take `input_of_welded`'s input vertex). False, nothing appended, when there is no
// such corner (each corner on a split edge's line).
bool split_face(std::span<const uint32_t> welded_face, std::span<const uint32_t> input_face,
                std::span<const EdgeSplit> splits, const std::vector<uint32_t>& input_of_welded,
                std::vector<Triangle>& welded_out, std::vector<Triangle>& input_out);

}  // namespace spheremap
