#include "core/io/mesh_format.h"

#include <algorithm>
#include <cctype>

#include "core/io/draco_file.h"
#include "core/io/mni_obj.h"
#include "core/io/obj.h"
#include "core/io/off.h"
#include "core/io/off_binary.h"
#include "core/io/ply.h"
#include "core/io/shown_bytes.h"
#include "core/io/stl.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

// The first word of the first line that is neither blank nor a '#' comment.
std::string_view first_word(std::string_view text) {
  size_t pos = 0;
  // A bounded look: the first 64 KiB decide (exporters write long comment headers).
  const size_t end_of_look = std::min<size_t>(text.size(), 64 * 1024);
  while (pos < end_of_look) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    const size_t start = l.find_first_not_of(" \t\r");
    if (start == std::string_view::npos || l[start] == '#') continue;
    l.remove_prefix(start);
    return l.substr(0, l.find_first_of(" \t\r"));
  }
  return {};
}

bool is_obj_statement(std::string_view word) {
  static constexpr std::string_view kStatements[] = {"v", "vt", "vn", "vp",     "f",     "l",
                                                     "o", "g",  "s",  "mtllib", "usemtl"};
  return std::find(std::begin(kStatements), std::end(kStatements), word) != std::end(kStatements);
}

}  // namespace

const char* const kReadableExtensions = "'.obj', '.off', '.stl', '.ply', '.drc', '.glb' or '.gltf'";

const char* format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::kGlb:
      return "glb";
    case MeshFormat::kGltf:
      return "gltf";
    case MeshFormat::kObj:
      return "obj";
    case MeshFormat::kOff:
      return "off";
    case MeshFormat::kStl:
      return "stl";
    case MeshFormat::kPly:
      return "ply";
    case MeshFormat::kDrc:
      return "drc";
  }
  return "";
}

std::optional<MeshFormat> format_from_extension(std::string_view extension) {
  std::string ext(extension);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (MeshFormat f : {MeshFormat::kGlb, MeshFormat::kGltf, MeshFormat::kObj, MeshFormat::kOff,
                       MeshFormat::kStl, MeshFormat::kPly, MeshFormat::kDrc})
    if (ext == format_name(f)) return f;
  return std::nullopt;
}

std::string lowercase_extension(std::string_view path) {
  const size_t dot = path.find_last_of('.');
  const size_t slash = path.find_last_of("/\\");
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return "";
  std::string ext(path.substr(dot + 1));
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::optional<MeshFormat> sniff_mesh_format(std::string_view bytes) {
  if (bytes.substr(0, 4) == "glTF") return MeshFormat::kGlb;
  if (bytes.substr(0, 5) == "DRACO") return MeshFormat::kDrc;
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);  // a UTF-8 byte order mark
  if (is_binary_stl(bytes)) return MeshFormat::kStl;
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 4) == "ply\r") return MeshFormat::kPly;
  const size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos) return std::nullopt;
  if (bytes[start] == '{') return MeshFormat::kGltf;
  if (bytes.substr(start, 5) == "solid") return MeshFormat::kStl;
  const std::string_view word = first_word(bytes);
  if (word == "OFF") return MeshFormat::kOff;
  if (is_obj_statement(word) || looks_like_mni_obj(bytes)) return MeshFormat::kObj;
  return std::nullopt;
}

PolygonMesh parse_mesh_text(std::string_view bytes, MeshFormat format, const MeshLimits& limits) {
  if (bytes.empty()) throw InputError("parse", "empty file (0 bytes)");
  const bool binary_off = format == MeshFormat::kOff && is_binary_off(bytes);
  if ((format == MeshFormat::kObj || format == MeshFormat::kOff) && !binary_off) {
    // A text format with NUL bytes is some other file (a PNG renamed .obj read as OBJ
    // found "no faces"); say what it starts with, and what it looks like when we know.
    if (const size_t nul = bytes.substr(0, 65536).find('\0'); nul != std::string_view::npos) {
      auto upper = [](MeshFormat f) {
        std::string name = format_name(f);
        for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        return name;
      };
      const std::optional<MeshFormat> looks = sniff_mesh_format(bytes);
      throw InputError(
          "parse",
          "not an " + upper(format) + " file: it holds binary bytes (a NUL at byte " +
              std::to_string(nul) + ", line " +
              std::to_string(1 + std::count(bytes.begin(), bytes.begin() + nul, '\n')) +
              "; it starts with " + shown_prefix(bytes) + ")" +
              (looks && *looks != format ? "; it looks like " + upper(*looks) : std::string()));
    }
  }
  switch (format) {
    case MeshFormat::kObj:
    case MeshFormat::kOff: {
      // An MNI surface shares Wavefront's .obj extension (mni_obj.h).
      if (format == MeshFormat::kObj && looks_like_mni_obj(bytes))
        return parse_mni_obj(bytes, limits);
      PolygonMesh mesh = format == MeshFormat::kObj ? parse_obj(bytes)
                         : binary_off               ? parse_off_binary(bytes)
                                                    : parse_off(bytes);
      const size_t triangles = mesh.indices.size() - 2 * mesh.face_count();
      if (mesh.vertex_count() > limits.max_vertices || triangles > limits.max_triangles)
        throw InputError("too_large", std::string(format_name(format)) + ": " +
                                          std::to_string(mesh.vertex_count()) + " vertices and " +
                                          std::to_string(triangles) +
                                          " triangles, over the limits of " +
                                          std::to_string(limits.max_vertices) + " and " +
                                          std::to_string(limits.max_triangles));
      return mesh;
    }
    case MeshFormat::kStl:
      return parse_stl(bytes, limits);
    case MeshFormat::kPly:
      return parse_ply(bytes, limits);
    case MeshFormat::kDrc:
      return read_draco_file({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()},
                             limits);
    case MeshFormat::kGlb:
    case MeshFormat::kGltf:
      break;
  }
  throw InputError("parse", std::string("parse_mesh_text cannot read ") + format_name(format) +
                                " (glTF goes through read_gltf)");
}

}  // namespace spheremap
