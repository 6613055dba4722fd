#include "core/prepare/handle_opening.h"

#include <algorithm>
#include <vector>

#include "core/mesh/submesh.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/open_part_cuts.h"
#include "core/prepare/vertex_split.h"

namespace spheremap {
namespace {

// Whether a part without its caps (`topology` its analyze_topology, pinches split) is one
// open sphere that can be cut into a disc, or falls apart at the split pinches into pieces
// that each can. Later cycles can run across earlier caps, so the cuts can together part a
// piece but for a vertex two of them touch at: Prusa's cable holder (11 handles) fell into
// two open spheres, and kept caps 3.9% of its diagonal off (remesh at 128: 4.08%; opened
// and each piece doubled: 2.26%).
bool opens_into_discs(const PolygonMesh& part, const TopologyReport& topology,
                      const StopCheck* stop) {
  if (topology.component_faces.size() <= 1) return can_become_disc(topology, part.indices.size());
  if (!topology.manifold()) return false;
  for (const std::vector<uint32_t>& faces : connected_part_faces(part, stop)) {
    const MeshPart piece = submesh(part, faces);
    if (!can_become_disc(analyze_topology(piece.mesh, stop), piece.mesh.indices.size()))
      return false;
  }
  return true;
}

}  // namespace

HandleOpening open_far_handles(PolygonMesh& mesh, const HandleClosing& closed, double near,
                               const StopCheck* stop) {
  HandleOpening result;
  std::vector<const HandleClosing::ClosedPart*> far;
  for (const HandleClosing::ClosedPart& part : closed.closed_parts) {
    if (part.farthest > near && !part.genus_left)
      far.push_back(&part);
    else
      result.farthest_fill = std::max(result.farthest_fill, part.farthest);
  }
  if (far.empty()) return result;
  std::vector<char> removed(mesh.face_count(), 0);
  auto mark = [&](const HandleClosing::ClosedPart& part, char value) {
    std::fill_n(removed.begin() + static_cast<std::ptrdiff_t>(part.first_fill), part.fills, value);
  };
  for (const HandleClosing::ClosedPart* part : far) mark(*part, 1);
  // The parts as they would be without their caps. A later cycle may have run across an
  // earlier cap, so the faces left can fall apart: the part's caps must touch one piece (a
  // part opened into pieces, each doubled, was measured farther than capped: the allegro
  // hand's base 2.75% of its diagonal, capped 1.99%), an open sphere a cut makes a disc.
  PolygonMesh opened = mesh;
  erase_faces(opened, removed);
  const std::vector<std::vector<uint32_t>> parts = connected_part_faces(opened, stop);
  std::vector<uint32_t> part_of(mesh.vertex_count(), kUnreferenced);
  for (uint32_t p = 0; p < parts.size(); ++p)
    for (uint32_t f : parts[p])
      for (uint32_t v : opened.face(f)) part_of[v] = p;
  bool split_pinches = false;
  std::vector<uint32_t> pieces;
  for (const HandleClosing::ClosedPart* part : far) {
    if (stop) stop->check();
    pieces.clear();
    for (size_t f = part->first_fill; f < part->first_fill + part->fills; ++f)
      for (uint32_t v : mesh.face(f))
        if (part_of[v] != kUnreferenced) pieces.push_back(part_of[v]);
    std::sort(pieces.begin(), pieces.end());
    pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
    // One piece, one open sphere (once two cuts' touching holes are split apart).
    bool opens = pieces.size() == 1;
    if (opens) {
      MeshPart own = submesh(opened, parts[pieces[0]]);
      TopologyReport topology = analyze_topology(own.mesh, stop);
      if (topology.non_manifold_vertices > 0 &&
          split_non_manifold_vertices(own.mesh, stop).vertices_added > 0) {
        topology = analyze_topology(own.mesh, stop);
        split_pinches = true;
      }
      opens = opens_into_discs(own.mesh, topology, stop);
    }
    if (!opens) {
      mark(*part, 0);
      result.farthest_fill = std::max(result.farthest_fill, part->farthest);
      continue;
    }
    ++result.parts_opened;
    result.handles_opened += part->cuts;
    result.faces_removed += part->fills;
  }
  if (result.faces_removed == 0) return result;
  erase_faces(mesh, removed);
  if (split_pinches) result.vertices_split = split_non_manifold_vertices(mesh, stop).vertices_split;
  return result;
}

}  // namespace spheremap
