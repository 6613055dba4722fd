#include "core/prepare/interior_walls.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/mesh/union_find.h"
#include "core/prepare/edge_pairing.h"
#include "core/prepare/hole_filling.h"  // undirected_edge_key
#include "core/prepare/vertex_split.h"

namespace spheremap {

InteriorWalls double_interior_walls(PolygonMesh& mesh, const StopCheck* stop) {
  InteriorWalls result;
  const uint32_t faces = static_cast<uint32_t>(mesh.face_count());
  const std::vector<EdgeCorner> corners = sorted_edge_corners(mesh, stop);
  UnionFind sheets = manifold_sheets(corners, faces);
  // At an edge of three faces, two run one way and the odd one the other way; of the two,
  // the wall is the one inside the solid that the odd face and the other bound (met first
  // turning from the odd face toward its solid: larger angles about a -> b for a face
  // running b -> a). A sheet is a wall when it is the wall at every edge of three it has,
  // and has no edge of one face or of more than three.
  std::vector<char> not_wall(faces, 0), is_rim(faces, 0);
  std::vector<uint32_t> far;
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    if (j - i == 2) continue;
    if (j - i != 3) {
      for (size_t k = i; k < j; ++k) not_wall[sheets.find(corners[k].face)] = 1;
      continue;
    }
    const EdgeCorner* c = &corners[i];
    const size_t odd = c[0].forward == c[1].forward ? 2 : c[0].forward == c[2].forward ? 1 : 0;
    const EdgeCorner& s1 = c[(odd + 1) % 3];
    const EdgeCorner& s2 = c[(odd + 2) % 3];
    far = {c[odd].far, s1.far, s2.far};
    const std::vector<double> angle = angles_about_edge(mesh, static_cast<uint32_t>(c->edge >> 32),
                                                        static_cast<uint32_t>(c->edge), far);
    const uint32_t sheet_odd = sheets.find(c[odd].face);
    const uint32_t sheet1 = sheets.find(s1.face), sheet2 = sheets.find(s2.face);
    const bool distinct = sheet_odd != sheet1 && sheet_odd != sheet2 && sheet1 != sheet2;
    if (angle.empty() || !distinct || s1.forward != s2.forward) {
      not_wall[sheet_odd] = not_wall[sheet1] = not_wall[sheet2] = 1;
      continue;
    }
    auto turn = [&](double to) { return std::fmod(to - angle[0] + 4 * M_PI, 2 * M_PI); };
    const bool first =
        c[odd].forward ? turn(angle[1]) > turn(angle[2]) : turn(angle[1]) < turn(angle[2]);
    const uint32_t wall = first ? sheet1 : sheet2;
    is_rim[wall] = 1;
    not_wall[sheet_odd] = not_wall[first ? sheet2 : sheet1] = 1;
  }
  auto is_wall = [&](uint32_t face) {
    const uint32_t sheet = sheets.find(face);
    return is_rim[sheet] && !not_wall[sheet];
  };
  std::vector<uint32_t> wall_faces;
  for (uint32_t f = 0; f < faces; ++f)
    if (is_wall(f)) wall_faces.push_back(f);
  if (wall_faces.empty()) return result;
  EdgePairs pairs;
  std::vector<uint32_t> copy_of(faces, UINT32_MAX);
  for (uint32_t f : wall_faces) {
    copy_of[f] = static_cast<uint32_t>(mesh.face_count());
    std::vector<uint32_t> reversed(mesh.face(f).begin(), mesh.face(f).end());
    std::reverse(reversed.begin(), reversed.end());
    mesh.add_face(reversed);
  }
  result.faces_added = wall_faces.size();
  for (uint32_t f = 0; f < faces; ++f)  // a sheet is counted at its root face
    if (sheets.find(f) == f && is_wall(f)) ++result.walls;
  // The pairs: at a rim edge the wall's face with the solid's face running the other way,
  // its copy with the other; at an edge inside the wall, the wall's faces together and
  // their copies together.
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    std::vector<std::pair<uint32_t, uint32_t>> edge_pairs;
    auto pair = [&](uint32_t a, uint32_t b) {
      edge_pairs.push_back({a, b});
      edge_pairs.push_back({b, a});
    };
    const bool in_wall = copy_of[corners[i].face] != UINT32_MAX;
    if (j - i == 2 && in_wall && copy_of[corners[i + 1].face] != UINT32_MAX) {
      pair(corners[i].face, corners[i + 1].face);
      pair(copy_of[corners[i].face], copy_of[corners[i + 1].face]);
    } else if (j - i == 3) {
      size_t w = j;
      for (size_t k = i; k < j; ++k)
        if (copy_of[corners[k].face] != UINT32_MAX) w = k;
      if (w == j) continue;
      for (size_t k = i; k < j; ++k) {
        if (k == w) continue;
        // A solid's face running against the wall's face closes with it; the other solid's,
        // with the copy (which runs the other way).
        pair(corners[k].forward != corners[w].forward ? corners[w].face : copy_of[corners[w].face],
             corners[k].face);
      }
    }
    if (!edge_pairs.empty()) pairs.emplace(corners[i].edge, std::move(edge_pairs));
  }
  result.vertices_added = split_non_manifold_vertices(mesh, stop, &pairs).vertices_added;
  return result;
}

}  // namespace spheremap
