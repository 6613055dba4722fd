// Cleaning that moves no vertex ("clean only what is safe"): faces the weld collapsed,
// exact duplicate faces (double-sided copies), T-junction cracks (faces split at the other
// side's vertices, t_junctions.h), and faces whose orientation disagrees with
// their neighbours'. It decides on the welded mesh (glTF splits vertices at seams, so only
// welded ids tell which faces touch) and edits the input's own faces, so every later
// stage (the weld again, the outputs, the glTF look's face ranges) sees one consistent
// input.
//
// Preconditions: none; any polygon mesh. Faces are kept in input order. What it leaves
// alone: non-manifold edges and vertices, boundaries, a pinched polygon (a vertex twice,
// not in a row), a part that cannot be oriented (a Moebius strip): the topology checks
// report those.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct FaceCleanup {
  PolygonMesh mesh;                   // the input's vertices, the cleaned faces
  std::vector<uint32_t> source_face;  // per face of mesh: its index in the input
  size_t collapsed_faces = 0;         // dropped: fewer than 3 distinct corners once welded
  size_t shortened_faces = 0;         // polygons that lost corners welded onto their neighbour
  size_t duplicate_faces = 0;         // dropped: the same welded corners as an earlier face
  size_t t_junctions_zipped = 0;      // vertices inserted into boundary edges (t_junctions.h)
  size_t faces_split = 0;             // faces replaced by a fan to take them in
  size_t flipped_faces = 0;           // reversed to agree with the rest of their part
  size_t reoriented_parts = 0;        // parts whose orientation was made consistent
  bool changed() const {
    return collapsed_faces + shortened_faces + duplicate_faces + t_junctions_zipped +
               flipped_faces >
           0;
  }
};

// weld_tolerance as weld(): relative to the bounding-box diagonal, 0 = equal positions.
// A part made consistent is made outward when it is closed (positive signed volume),
// else keeps the orientation of most of its faces; parts already consistent are untouched.
// `stop` (may be null) is asked as it goes, as in weld().
FaceCleanup clean_faces(const PolygonMesh& input, double weld_tolerance, StopCheck* stop = nullptr);

}  // namespace spheremap
