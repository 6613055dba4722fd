// Binary OFF: the header line "OFF BINARY", then 32-bit counts (vertices, faces, edges),
// float32 positions, and per face its corner count and 32-bit indices. Geomview's layout is
// big endian with a colour count (and its floats) after each face; the Polygon Mesh
// Processing Library (pmp) writes little endian without it (its data/off/beetle.off).
#pragma once

#include <string_view>

#include "core/mesh/mesh.h"

namespace spheremap {

// True when `bytes` begins with the line "OFF BINARY" (the reader below is then the one).
bool is_binary_off(std::string_view bytes);

// Reads the layout whose faces end exactly at the file's end: the byte order whose counts
// fit in the file (big endian when both do), faces with or without a colour count.
// Throws InputError("parse") when neither layout reads the whole file, on an index out of
// range, or on counts the file cannot hold (checked before anything is allocated).
PolygonMesh parse_off_binary(std::string_view bytes);

}  // namespace spheremap
