// Meshes the tests make themselves, so a checkout without ../shared/meshes still tests
// real behaviour: closed genus-0 shapes (sphere, quad cube, a long thin "finger" tube with
// polygon faces) and invalid ones (torus, holes, two components, a pinched vertex).
#pragma once

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
// Torus (genus 1) of `around` x `along` quads.
PolygonMesh torus(int around, int along);
// Two disjoint tetrahedra.
PolygonMesh two_tetrahedra();
// Two tetrahedra sharing exactly one vertex (every edge manifold, that vertex is not).
PolygonMesh pinched_tetrahedra();
// The mesh with every face reversed (inward orientation).
PolygonMesh reversed(PolygonMesh mesh);
// The mesh without face f (a hole).
PolygonMesh without_face(const PolygonMesh& mesh, size_t f);

}  // namespace spheremap::testing
