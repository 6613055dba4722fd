#include "core/io/off.h"

#include <vector>

#include "core/io/text_reader.h"

namespace spheremap {
namespace {

// Skips blank (and comment-only) lines.
bool next_content_line(TextReader& reader) {
  while (reader.next_line())
    if (reader.rest().find_first_not_of(" \t") != std::string_view::npos) return true;
  return false;
}

// OFF is a stream of whitespace-separated numbers: a record usually takes a line, but some
// writers (libigl's tutorial data) break a face over several. The next number may then be
// on a later line; what follows a record on its last line (colours) is skipped by starting
// the next record on a new line.
void need_token(TextReader& reader, const std::string& what) {
  if (reader.rest().find_first_not_of(" \t") == std::string_view::npos &&
      !next_content_line(reader))
    reader.fail("file ends before " + what);
}

}  // namespace

PolygonMesh parse_off(std::string_view text) {
  TextReader reader(text, "OFF");
  if (!next_content_line(reader)) reader.fail("empty file");
  std::string_view magic = reader.token();
  if (magic != "OFF") reader.fail("expected the 'OFF' header, found '" + std::string(magic) + "'");
  if (reader.rest().find_first_not_of(" \t") == std::string_view::npos &&
      !next_content_line(reader))
    reader.fail("missing the vertex and face counts");
  long long vertex_count = reader.integer("the vertex count");
  long long face_count = reader.integer("the face count");
  // Every vertex takes at least 6 characters and every face 8: a bound from the file size.
  const long long size = static_cast<long long>(text.size());
  if (vertex_count < 0 || face_count < 0 || vertex_count > size / 6 || face_count > size / 8)
    reader.fail("counts " + std::to_string(vertex_count) + " vertices, " +
                std::to_string(face_count) + " faces do not fit in a " + std::to_string(size) +
                "-byte file");

  PolygonMesh mesh;
  mesh.positions.reserve(static_cast<size_t>(vertex_count));
  for (long long i = 0; i < vertex_count; ++i) {
    if (!next_content_line(reader)) reader.fail("file ends before vertex " + std::to_string(i));
    const std::string vertex = "vertex " + std::to_string(i) + " is complete";
    Vec3 p;
    p.x = reader.number("x");
    need_token(reader, vertex);
    p.y = reader.number("y");
    need_token(reader, vertex);
    p.z = reader.number("z");
    mesh.positions.push_back(p);
  }
  std::vector<uint32_t> corners;
  for (long long f = 0; f < face_count; ++f) {
    if (!next_content_line(reader)) reader.fail("file ends before face " + std::to_string(f));
    long long n = reader.integer("the face size");
    if (n < 3 || n > vertex_count)
      reader.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " corners");
    corners.clear();
    for (long long k = 0; k < n; ++k) {
      need_token(reader, "face " + std::to_string(f) + " is complete");
      long long index = reader.integer("a face index");
      // One past the last is what a file counting its vertices from 1 names first
      // (kaolin's sample OFF): said, as OFF counts from 0.
      if (index < 0 || index >= vertex_count)
        reader.fail("face index " + std::to_string(index) + " is out of range (" +
                    std::to_string(vertex_count) + " vertices" +
                    (index == vertex_count ? ", counted from 0: does the file count from 1?" : "") +
                    ")");
      corners.push_back(static_cast<uint32_t>(index));
    }
    mesh.add_face(corners);
  }
  return mesh;
}

}  // namespace spheremap
