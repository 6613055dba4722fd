// Thin two-sided shells (issue "Reach I" item 6): the envelope of an open sheet is a
// closed surface about 3 voxels thick (1.2e-2 of the diagonal at the default 256), the
// sheet doubled with a rim. A jittered grid sheet thickened that way has pinhole handles
// where the grid's jagged edge and the bowl's slope meet; the envelope's cut rule
// (EnvelopeRule::kCut) opens them into slits, as the reach-first rule did on three real
// assets (bunny.ply, beetle.obj, lato315.ply), whose cut envelopes the map did not finish.
#pragma once

#include <string>
#include <vector>

#include "core/mesh/mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap::testing {

// Open sheets over [-1, 1]^2: a grid of n x n cells, corners jittered by up to 0.35 of a
// cell (the same every run), two triangles per cell, a cell's triangle kept when its
// centroid is inside the outline; lifted to a wavy bowl z = 0.7 (x^2 + y^2) + 0.06 sin 6x
// cos 5y. Not manifold at every vertex (the jagged edge): an envelope's input, not a map's.
// The outlines: "fingers" (a disk with three long lobes), "perforated" (a disk with 17
// round holes), "spiral" (a spiral band).
std::vector<NamedMesh> open_sheets(int n = 120);

}  // namespace spheremap::testing
