// Polygon mesh (faces of any size >= 3) and its fan triangulation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/vec3.h"

namespace spheremap {

using Triangle = std::array<uint32_t, 3>;

// Faces are stored as one index array with offsets (CSR): face f is
// indices[offsets[f] .. offsets[f+1]). offsets always starts with 0.
struct PolygonMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;

  size_t vertex_count() const { return positions.size(); }
  size_t face_count() const { return offsets.size() - 1; }
  size_t face_size(size_t f) const { return offsets[f + 1] - offsets[f]; }
  std::span<const uint32_t> face(size_t f) const {
    return {indices.data() + offsets[f], face_size(f)};
  }
  void add_face(std::span<const uint32_t> corners);
  bool is_triangle_mesh() const { return indices.size() == 3 * face_count(); }
};

// The face of a corner (a slot in mesh.indices). O(log faces).
uint32_t face_of_slot(const PolygonMesh& mesh, uint32_t slot);
// The vertex of the corner before `slot` in its face (O(log faces), whatever its size).
uint32_t vertex_before(const PolygonMesh& mesh, uint32_t slot);

// Fan triangulation (a, a+k, a+k+1) of every face, in face order; triangle_face[t] is
// the face triangle t came from. Used by folds, areas, the hierarchy and insertion.
// The apex a of a polygon is its first corner whose diagonals are neither a mesh edge
// nor another polygon's diagonal (a fan from corner 0 makes non-manifold edges on
// real quad meshes); conflicting_faces counts polygons where no corner qualified.
struct FanTriangulation {
  std::vector<Triangle> triangles;
  std::vector<uint32_t> triangle_face;
  size_t conflicting_faces = 0;
};
FanTriangulation fan_triangulate(const PolygonMesh& mesh);

// The same mesh with each polygon's corners rotated so that its fan apex comes first: the
// fan from the first corner, which three.js, Blender and most OBJ loaders use, is then
// the triangulation fan_triangulate gives (and the map was certified on). Triangles are
// unchanged. Vertices and face order are kept; fan_triangulate of the result gives the
// same triangles.
PolygonMesh apex_first(const PolygonMesh& mesh);
// The same with the apexes chosen on `decided_on`: the same faces (count and sizes) over
// other vertex ids, such as the input's faces named by their welded vertices. The input
// layout splits vertices at seams, so its own edges can pick another apex than the welded
// mesh the map was certified on; this writes the certified one.
PolygonMesh apex_first(const PolygonMesh& mesh, const PolygonMesh& decided_on);

// Vertex -> incident triangles, as CSR, triangle ids ascending (a fixed order keeps
// every gather over it deterministic).
struct VertexTriangles {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> triangles;
  std::span<const uint32_t> of(size_t v) const {
    return {triangles.data() + offsets[v], offsets[v + 1] - offsets[v]};
  }
};
VertexTriangles vertex_triangles(std::span<const Triangle> triangles, size_t vertex_count);

// Signed volume enclosed by the triangles (divergence theorem) on the positions centred
// and scaled (center_and_scale): its sign is the orientation, < 0 means inward-facing.
double signed_volume(std::span<const Vec3> positions, std::span<const Triangle> triangles);

// Whether a closed surface faces inward: its signed volume (times 6) below minus a tiny
// share of its area (twice_area: the sum of |cross| of its triangles), both on the
// positions centred and scaled. A surface enclosing no volume (an open sheet closed by its
// own back: sheet_doubling.h) has a signed volume of rounding noise, whose sign moves with
// the order of the sum: the map's reordered copy and the outputs' own triangles disagreed,
// and the float32 check then found every triangle folded. Below 1e-9 of its area (where a
// solid's volume is some tenth of it) it is taken for none, and the surface as it runs.
bool volume_runs_inward(double six_volume, double twice_area);
// The same for the triangles over positions (centred and scaled here).
bool runs_inward(std::span<const Vec3> positions, std::span<const Triangle> triangles);

// The centre of the positions' axis-aligned bounding box (origin when empty).
Vec3 bounding_box_center(std::span<const Vec3> positions);

// The similarity that moves the positions' bounding box's centre to the origin and scales
// them by a power of two (exact) so that the largest coordinate is in [1, 2): computed on
// it, nothing depends on where a mesh sits or on its units (quadric errors of a mesh 1e4
// from the origin cancelled to noise; areas of a mesh at 1e200 overflow). apply() moves
// any point (a second surface compared with this one) the same way.
struct UnitFrame {
  int exponent = 0;   // first scaled by 2^-exponent,
  Vec3 center;        // then moved by -center,
  int exponent2 = 0;  // then scaled by 2^-exponent2
  Vec3 apply(const Vec3& p) const;
  double length_in_input_units(double length) const;
};
// Non-finite positions are ignored for the scale (they are rejected before mapping).
UnitFrame unit_frame(std::span<const Vec3> positions);

// Every position moved by unit_frame(positions).
void center_and_scale(std::span<Vec3> positions);
// A copy of positions moved by unit_frame(positions): for figures that are ratios (volume
// sign, stretch, area shares) whose sums would overflow or underflow in extreme units.
std::vector<Vec3> centered_and_scaled(std::span<const Vec3> positions);

}  // namespace spheremap
