#include "core/io/mesh_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/io/mesh_format.h"
#include "core/io/obj.h"
#include "core/io/text_reader.h"
#include "core/mesh/input_error.h"

namespace spheremap {

PolygonMesh read_mesh_file(const std::string& path, const GltfReadOptions& gltf,
                           GltfReadStats* stats, GltfAppearance* appearance) {
  const std::optional<MeshFormat> format = format_from_extension(lowercase_extension(path));
  if (!format)
    throw InputError(
        "io", "cannot read '" + path + "': unknown extension (use " + kReadableExtensions + ")");
  const std::string text = read_file(path);
  if (*format != MeshFormat::kGlb && *format != MeshFormat::kGltf)
    return parse_mesh_text(text, *format);
  // Buffers a .gltf (or a GLB) names by URI are read from its own folder only.
  const size_t slash = path.find_last_of('/');
  const FolderResources folder(slash == std::string::npos ? "." : path.substr(0, slash + 1));
  return read_gltf({reinterpret_cast<const uint8_t*>(text.data()), text.size()}, gltf, stats,
                   &folder, appearance);
}

void write_mesh_file(const std::string& path, const PolygonMesh& mesh) {
  if (lowercase_extension(path) != "obj")
    throw InputError("io", "cannot write '" + path + "': use the .obj extension");
  write_binary_file(path, format_obj(mesh));
}

void write_binary_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw OutputError("cannot write '" + path + "': " + std::strerror(errno));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw OutputError("cannot write '" + path + "': " + std::strerror(errno));
}

}  // namespace spheremap
