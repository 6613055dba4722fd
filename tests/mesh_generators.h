// Meshes the tests make themselves, so a checkout without ../shared/meshes still tests
// real behaviour: closed genus-0 shapes (sphere, quad cube, a long thin "finger" tube with
// polygon faces) and invalid ones (torus, holes, two components, a pinched vertex).
#pragma once

#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap::testing {

// Icosahedron subdivided `levels` times (4x faces each), on the unit sphere, outward.
PolygonMesh icosphere(int levels);
// Cube [-1,1]^3 with each face split into n x n quads, outward.
PolygonMesh quad_cube(int n);
// Closed tube of `around` x `along` quads (radius 1, length `length`), each end closed by
// one `around`-gon: a long thin protrusion with n-gons.
PolygonMesh capped_tube(int around, int along, double length);
// capped_tube(12, 30, 12) bent around 306 degrees: genus 0 but far from star-shaped; the
// paper's loop never unfolds it (469 folds after 20000 iterations), the default method does.
PolygonMesh horseshoe();
// The stress set (hard shapes beyond the corpus, ALGORITHM §F): each an embedding of the
// sphere, so genus 0 and closed by construction.
//
// `base` on the unit sphere with a limb along each direction: a vertex at angle a from
// the nearest direction moves to radius clamp(thickness / a, 1, 1 + length), a tube of
// radius ~thickness with a flat cap; its triangles get long and thin along the limb.
PolygonMesh with_limbs(PolygonMesh base, std::span<const Vec3> directions, double length,
                       double thickness);
// Each point turned about the z axis by radians_per_unit x its distance from the axis:
// every cylinder about z turns rigidly, so an embedding stays one; limbs in the xy
// plane curl into spirals (not star-shaped).
PolygonMesh swirled(PolygonMesh mesh, double radians_per_unit);
// Each point turned about the z axis by radians_per_unit x z (a twist).
PolygonMesh twisted(PolygonMesh mesh, double radians_per_unit);
// Positions scaled per axis.
PolygonMesh scaled(PolygonMesh mesh, const Vec3& factors);
// quad_cube(n) projected onto the unit sphere (quad-dominant sphere).
PolygonMesh quad_sphere(int n);
// A prism over the closed plane polygon `outline` (counter-clockwise), z from -height / 2
// to height / 2, as CAD exporters write one: one band of side quads, each cap a fan of
// triangles from a centre vertex (fan_caps) or one polygon.
PolygonMesh prism(std::span<const std::array<double, 2>> outline, double height, bool fan_caps);
struct NamedMesh {
  std::string name;
  PolygonMesh mesh;
};
// The stress set: fingers (curled), spikes, a twisted blade, quad limbs, a very long
// tube, two CAD prisms (a 256-sided cylinder with fan caps, a 32-pointed star with
// polygon caps), and `with_million`: fingers on 1.3M triangles.
std::vector<NamedMesh> stress_meshes(bool with_million);
// `count` shapes drawn from `seed` (the same seed, the same shapes): a triangle or quad
// sphere (5K-20K faces) with 1-30 limbs in random directions (0.5-10 long, 0.03-0.25
// thick), swirled, twisted and stretched by random amounts: shapes no one tuned for.
std::vector<NamedMesh> random_stress_meshes(int count, unsigned seed);

// A plate of unit cells (cols x rows, `thickness` thick) with a through-hole at each cell
// of `holes`: quads on top, bottom and the walls, outward. Genus: the number of holes.
PolygonMesh plate_with_holes(int cols, int rows, const std::vector<std::pair<int, int>>& holes,
                             double thickness = 1);

// Torus (genus 1) of `around` x `along` quads.
PolygonMesh torus(int around, int along);
// Two disjoint tetrahedra.
PolygonMesh two_tetrahedra();
// Two tetrahedra sharing exactly one vertex (every edge manifold, that vertex is not).
PolygonMesh pinched_tetrahedra();
// A unit cube (12 triangles) and a tetrahedron in its corner at the origin, each with
// vertices of its own: welded, they share 4 vertices and 3 edges of 4 faces, and the
// tetrahedron's slanted face is inside the cube. With `fin`, also a triangle hanging off
// the cube's edge at x = y = 1 (an edge of 3 faces, which no split can share out).
PolygonMesh cube_and_corner_tetrahedron(bool fin = false);
// The mesh with every face reversed (inward orientation).
PolygonMesh reversed(PolygonMesh mesh);
// The mesh without face f (a hole).
PolygonMesh without_face(const PolygonMesh& mesh, size_t f);
// The faces of icosphere(levels) above z = 0, welded: an open dome whose one hole is too
// large to close (its fill would be about half its area).
PolygonMesh dome(int levels);
// The faces of icosphere(levels) with |z| < 0.6, welded: an open band (genus 0, two holes,
// each too large to close), which prepare=auto cuts into a disc and closes by its back
// (open_part_cuts.h, sheet_doubling.h).
PolygonMesh band(int levels);
// torus(around, along) without the quads of a patch on its outer side (a quarter of the
// way round each circle): genus 1 with one hole too large to fill, which prepare=auto wraps.
PolygonMesh holed_torus(int around, int along);
// A Moebius band of `segments` quads (a strip of width 1 around a circle of radius 2, turned
// half a turn on the way): open, one boundary loop, not orientable, so no repair maps it and
// prepare=auto wraps it.
PolygonMesh moebius_band(int segments);
// `count` separate quads (1 x 0.5, bent 0.3 along x, two triangles each) at positions drawn
// from std::mt19937(seed) in a 100^3 box: a scatter whose envelope merges them into one body
// of many blobs (bench/reach/scatter.py draws the same shape from Python's generator).
PolygonMesh quad_scatter(int count, unsigned seed);
// One mesh of several parts: each (mesh, offset) moved by its offset, in the order given.
PolygonMesh assembled(const std::vector<std::pair<PolygonMesh, Vec3>>& parts);

// A textured GLB of `mesh` (fan-triangulated) as exporters write one: every triangle's
// corners are vertices of their own (seams everywhere), TEXCOORD_0 is the planar
// projection (x, y) scaled to [0, 1], and a material holds an embedded 16 x 16 PNG of
// 4 x 4 squares in red, green, blue and white.
std::string textured_glb(const PolygonMesh& mesh);
// That texture's colour at (u, v) (nearest texel, clamped), 8-bit RGB.
std::array<int, 3> textured_glb_color(double u, double v);
// A GLB that draws `mesh` `count` times with EXT_mesh_gpu_instancing, the instances on a
// square grid 3 units apart (TRANSLATION only).
std::string instanced_glb(const PolygonMesh& mesh, size_t count);

}  // namespace spheremap::testing
