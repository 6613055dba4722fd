// The mesh file formats read, by file extension or by their first bytes (an upload
// whose content type says nothing), and reading the ones that need no side files.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/io/mesh_limits.h"
#include "core/mesh/mesh.h"

namespace spheremap {

enum class MeshFormat { kGlb, kGltf, kObj, kOff, kStl, kPly, kDrc };

// "glb", "gltf", "obj", "off", "stl", "ply", "drc" (a raw Draco file): the extension and the name
// in reports.
const char* format_name(MeshFormat format);
// "'.obj', '.off', '.stl', '.ply', '.drc', '.glb' or '.gltf'", for error messages.
extern const char* const kReadableExtensions;

// By extension, case-insensitive, without the dot ("STL" -> kStl); nullopt when unknown.
std::optional<MeshFormat> format_from_extension(std::string_view extension);
// The extension of a path or file name, lowercase, without the dot ("" when none).
std::string lowercase_extension(std::string_view path);

// From the bytes: GLB magic, Draco's magic "DRACO", a JSON object (glTF), "ply", binary STL's size
// rule or ASCII "solid", "OFF", or OBJ statements (v, f, vn, vt, o, g, s, mtllib, usemtl, #).
// nullopt when none fits.
std::optional<MeshFormat> sniff_mesh_format(std::string_view bytes);

// OBJ, OFF, STL, PLY or raw Draco bytes as a mesh (glTF needs its resources: read_gltf).
// Throws InputError("parse") as the format's reader does. `limits` are checked against
// the declared counts of STL, PLY and Draco before allocating; for OBJ and OFF, whose size is
// bounded by their text, on the mesh read. Over them: InputError("too_large").
PolygonMesh parse_mesh_text(std::string_view bytes, MeshFormat format,
                            const MeshLimits& limits = {});

}  // namespace spheremap
