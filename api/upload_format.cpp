#include "api/upload_format.h"

#include <algorithm>

namespace spheremap::api {
namespace {

struct NamedType {
  std::string_view type;
  MeshFormat format;
};
// Registered types first; the x- and vendor ones are what tools and browsers send.
constexpr NamedType kTypes[] = {
    {"model/gltf-binary", MeshFormat::kGlb},  {"model/gltf+json", MeshFormat::kGltf},
    {"model/obj", MeshFormat::kObj},          {"model/stl", MeshFormat::kStl},
    {"model/x.stl-binary", MeshFormat::kStl}, {"model/x.stl-ascii", MeshFormat::kStl},
    {"application/sla", MeshFormat::kStl},    {"application/vnd.ms-pki.stl", MeshFormat::kStl},
    {"application/ply", MeshFormat::kPly},    {"model/ply", MeshFormat::kPly},
    {"model/off", MeshFormat::kOff},          {"model/x-off", MeshFormat::kOff},
    {"application/x-off", MeshFormat::kOff},
};

std::string lowercase(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

const char* const kAcceptedMediaTypes =
    "model/gltf-binary (a .glb), model/gltf+json (a .gltf with embedded buffers), model/obj, "
    "model/stl, application/ply, model/off, application/octet-stream (the format read from the "
    "bytes), or multipart/form-data with a 'mesh' file part (the format from its file name), an "
    "optional 'options' JSON part and, for a .gltf with external files, one part per file named "
    "by its URI";

std::optional<MeshFormat> format_of_media_type(std::string_view type) {
  const std::string lower = lowercase(type.substr(0, type.find(';')));
  for (const NamedType& t : kTypes)
    if (lower == t.type) return t.format;
  return std::nullopt;
}

MeshFormat format_of_part(std::string_view filename, std::string_view content_type,
                          std::string_view bytes) {
  if (auto by_name = format_from_extension(lowercase_extension(filename))) return *by_name;
  if (auto by_type = format_of_media_type(content_type)) return *by_type;
  const std::optional<MeshFormat> sniffed = sniff_mesh_format(bytes);
  return sniffed.value_or(MeshFormat::kGlb);
}

}  // namespace spheremap::api
