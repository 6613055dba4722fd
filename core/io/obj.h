// Wavefront OBJ: positions and polygon faces. Reads `v`, `f` with v, v/vt, v//vn and
// v/vt/vn corners, negative (relative) indices, comments, CRLF and lines continued by a
// trailing backslash; ignores vt, vn, g, o, s, usemtl, mtllib, p and l (a file of lines
// and no faces is refused as such). Writes `v` and `f` lines only. MNI surfaces, which
// share the .obj extension, are read by mni_obj.h.
#pragma once

#include <string>
#include <string_view>

#include "core/mesh/mesh.h"

namespace spheremap {

// Throws InputError("parse") with the line number on malformed input or
// out-of-range indices; InputError("empty") for `l` lines and no faces.
PolygonMesh parse_obj(std::string_view text);
std::string format_obj(const PolygonMesh& mesh);

}  // namespace spheremap
