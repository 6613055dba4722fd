#include "core/io/mesh_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/io/obj.h"
#include "core/io/off.h"
#include "core/io/text_reader.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

std::string lowercase_extension(const std::string& path) {
  size_t dot = path.find_last_of('.');
  size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

PolygonMesh read_mesh_file(const std::string& path, const GltfReadOptions& gltf,
                           GltfReadStats* stats, GltfAppearance* appearance) {
  const std::string ext = lowercase_extension(path);
  if (ext != "obj" && ext != "off" && ext != "glb" && ext != "gltf")
    throw InputError(
        "io", "cannot read '" + path + "': unknown extension (use .obj, .off, .glb or .gltf)");
  const std::string text = read_file(path);
  if (ext == "glb" || ext == "gltf") {
    // Buffers a .gltf (or a GLB) names by URI are read from its own folder only.
    const size_t slash = path.find_last_of('/');
    const FolderResources folder(slash == std::string::npos ? "." : path.substr(0, slash + 1));
    return read_gltf({reinterpret_cast<const uint8_t*>(text.data()), text.size()}, gltf, stats,
                     &folder, appearance);
  }
  return ext == "obj" ? parse_obj(text) : parse_off(text);
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
