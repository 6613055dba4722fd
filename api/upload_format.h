// Which mesh format an upload is: by its content type, by the file name of a multipart
// part, or, when the type says nothing (application/octet-stream, text/plain), by its
// bytes, so that an OBJ sent as octet-stream is read as OBJ and not refused as bad glTF.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/io/mesh_format.h"

namespace spheremap::api {

// The format a media type names (lowercase, without parameters): model/gltf-binary,
// model/gltf+json, model/obj, model/stl (and application/sla, application/vnd.ms-pki.stl,
// model/x.stl-binary, model/x.stl-ascii), application/ply (and model/ply), model/off
// (and application/x-off, model/x-off). nullopt for any other.
std::optional<MeshFormat> format_of_media_type(std::string_view type);

// A multipart part: its file name's extension, else its content type, else its bytes.
// A .glb or .gltf part (or one whose bytes fit neither) is glTF, as before.
MeshFormat format_of_part(std::string_view filename, std::string_view content_type,
                          std::string_view bytes);

// "model/gltf-binary (a .glb), model/gltf+json (...), model/obj, ...": the 415's advice.
extern const char* const kAcceptedMediaTypes;

}  // namespace spheremap::api
