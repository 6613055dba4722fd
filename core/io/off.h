// OFF (Object File Format): header "OFF", counts "V F E", V positions, F faces
// "n i0 .. in-1" (0-based). Optional per-face colour values after the indices are ignored.
#pragma once

#include <string_view>

#include "core/mesh/mesh.h"

namespace spheremap {

// Throws InputError("parse") on malformed input, index out of range, or counts that
// the text cannot hold (so a forged header cannot make us allocate without bound).
PolygonMesh parse_off(std::string_view text);

}  // namespace spheremap
