// MNI .obj polygon surfaces (the Montreal Neurological Institute's BIC object format:
// CIVET's and BrainSuite's cortical surfaces, VTK's vtkMNIObjectReader), ASCII form. They
// share Wavefront's extension and nothing else: a Wavefront reader finds no `v` or `f` in
// them and reports an empty mesh. Cortical surfaces are closed genus-0 meshes, the
// classic input of a spherical map.
//
// The layout, whitespace-separated throughout (line breaks carry no meaning):
//   P ambient diffuse specular specular_exponent opacity n_points
//   n_points x y z, then n_points normals nx ny nz (not read)
//   n_items  colour_flag  colours (flag 0: one RGBA; 1: one per item; 2: one per point)
//   n_items end indices (polygon k ends before end[k]), then end[n_items - 1] point indices
// Other objects (L lines, M markers, T text, Q quad meshes) and the binary form (a
// lower-case letter first) are refused by name.
#pragma once

#include <string_view>

#include "core/io/mesh_limits.h"
#include "core/mesh/mesh.h"

namespace spheremap {

// True when the text's first token is an MNI object letter (P, L, M, T, Q, F, X, V)
// standing alone: none of them is a Wavefront statement.
bool looks_like_mni_obj(std::string_view text);

// The polygons and points of an ASCII `P` object. Every count is checked against the
// tokens the text can still hold before anything is allocated, and against `limits`;
// InputError("parse") names the field and the count or index that is wrong;
// InputError("empty") for the other objects, which hold no surface.
PolygonMesh parse_mni_obj(std::string_view text, const MeshLimits& limits = {});

}  // namespace spheremap
