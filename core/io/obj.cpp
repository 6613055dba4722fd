#include "core/io/obj.h"

#include <charconv>
#include <cstdio>
#include <vector>

#include "core/io/text_reader.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

// The vertex part of a face corner "v", "v/vt", "v//vn" or "v/vt/vn".
long long corner_vertex(TextReader& reader, std::string_view corner) {
  std::string_view v = corner.substr(0, corner.find('/'));
  long long index = 0;
  auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), index);
  if (v.empty() || ec != std::errc() || ptr != v.data() + v.size())
    reader.fail("bad face corner '" + std::string(corner) + "'");
  return index;
}

}  // namespace

PolygonMesh parse_obj(std::string_view text) {
  PolygonMesh mesh;
  TextReader reader(text, "OBJ");
  reader.join_continued_lines();
  std::vector<uint32_t> corners;
  size_t line_segments = 0;  // of `l` polylines: counted for the refusal, never stored
  // A 2D OBJ (triangulations of planar domains: libigl's, triangle's and rigid-ipc's 2D
  // meshes write "v x y") is read with z = 0, as tinyobjloader reads it. The first line
  // of each kind, so that a file mixing them is refused: a line cut short in a 3D file
  // is not a flat vertex.
  size_t first_planar = 0, first_spatial = 0;
  while (reader.next_line()) {
    std::string_view keyword = reader.token();
    if (keyword == "v") {
      Vec3 p;
      p.x = reader.number("x");
      p.y = reader.number("y");
      const bool planar = reader.rest().find_first_not_of(" \t") == std::string_view::npos;
      p.z = planar ? 0.0 : reader.number("z");
      size_t& first = planar ? first_planar : first_spatial;
      if (first == 0) first = reader.line_number();
      if (first_planar && first_spatial)
        reader.fail("a vertex of " + std::string(planar ? "2" : "3") + " coordinates where line " +
                    std::to_string(planar ? first_spatial : first_planar) + " has " +
                    (planar ? "3" : "2") + ": the file mixes 2D and 3D vertices");
      mesh.positions.push_back(p);
    } else if (keyword == "f") {
      corners.clear();
      const long long count = static_cast<long long>(mesh.positions.size());
      for (std::string_view tok = reader.token(); !tok.empty(); tok = reader.token()) {
        long long index = corner_vertex(reader, tok);
        long long resolved = index > 0 ? index - 1 : count + index;  // negative: relative
        if (index == 0 || resolved < 0 || resolved >= count)
          reader.fail("face index " + std::to_string(index) + " is out of range (" +
                      std::to_string(count) + " vertices so far)");
        corners.push_back(static_cast<uint32_t>(resolved));
      }
      if (corners.size() < 3)
        reader.fail("a face needs at least 3 corners, found " + std::to_string(corners.size()));
      mesh.add_face(corners);
    } else if (keyword == "l") {
      size_t points = 0;
      while (!reader.token().empty()) ++points;  // bounded by the line's length
      line_segments += points > 1 ? points - 1 : 0;
    }
    // Everything else (vt, vn, g, o, s, usemtl, mtllib, p, ...) carries nothing we map.
  }
  // Lines and no faces: said as lines (only points is a point cloud, said by the mesh
  // checks), under the check a mesh without faces fails.
  if (mesh.face_count() == 0 && line_segments > 0)
    throw InputError("empty", "the file has " + counted(mesh.vertex_count(), "vertex", "vertices") +
                                  " and " + counted(line_segments, "line segment") +
                                  ", no faces: spheremap maps triangle surfaces");
  return mesh;
}

std::string format_obj(const PolygonMesh& input) {
  // Polygons start at their fan apex, so a reader's fan from the first corner is the
  // triangulation the map was certified on (a quad's other diagonal can fold).
  const PolygonMesh mesh = apex_first(input);
  std::string out;
  out.reserve(mesh.vertex_count() * 40 + mesh.indices.size() * 8);
  char buf[128];
  for (const Vec3& p : mesh.positions) {
    int n = std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    out.append(buf, static_cast<size_t>(n));
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    out += 'f';
    for (uint32_t v : mesh.face(f)) {
      int n = std::snprintf(buf, sizeof buf, " %u", v + 1);
      out.append(buf, static_cast<size_t>(n));
    }
    out += '\n';
  }
  return out;
}

}  // namespace spheremap
