#include "core/prepare/sheet_doubling.h"

#include <optional>
#include <unordered_map>
#include <vector>

#include "core/mesh/half_edge_ends.h"
#include "core/mesh/topology.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/hole_filling.h"  // undirected_edge_key

namespace spheremap {
namespace {

// A back fan's triangle this small beside its longest edge squared is taken for no area
// (refused: a fan of such triangles around one point has no shape the map could follow).
constexpr double kFlatTriangle = 1e-12;

bool has_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest = std::max({squared_norm(b - a), squared_norm(c - b), squared_norm(a - c)});
  return norm(cross(b - a, c - a)) > kFlatTriangle * longest;
}

// The back of `part` (a disc): new vertices (after the part's own) and its triangles, in
// the part's numbering; nothing when a triangle would have no area.
struct Back {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

std::optional<Back> back_of(const PolygonMesh& part, const StopCheck* stop) {
  const uint32_t n = static_cast<uint32_t>(part.vertex_count());
  const HalfEdgeEnds ends(part);
  auto on_rim = [&](uint32_t a, uint32_t b) {  // a -> b a side of a face with nothing beyond
    return ends.has(a, b) && !ends.has(b, a);
  };
  std::vector<char> on_boundary(n, 0);
  for (size_t f = 0; f < part.face_count(); ++f) {
    const auto c = part.face(f);
    for (size_t i = 0; i < c.size(); ++i)
      if (on_rim(c[i], c[(i + 1) % c.size()]))
        on_boundary[c[i]] = on_boundary[c[(i + 1) % c.size()]] = 1;
  }
  if (stop) stop->check();

  Back back;
  auto add_vertex = [&](const Vec3& p) {
    back.positions.push_back(p);
    return n + static_cast<uint32_t>(back.positions.size() - 1);
  };
  auto position = [&](uint32_t v) { return v < n ? part.positions[v] : back.positions[v - n]; };
  // Interior vertices copied, boundary ones shared.
  std::vector<uint32_t> back_vertex(n);
  for (uint32_t v = 0; v < n; ++v)
    back_vertex[v] = on_boundary[v] ? v : add_vertex(part.positions[v]);
  // The front as the map will see it: its polygons fanned as fan_triangulate fans them (the
  // back adds no edge between two of the part's vertices, so their fans stay). An edge or
  // fan diagonal between two boundary vertices that is not a rim side gets a midpoint on
  // the back, which lies on the front.
  const std::vector<Triangle> front = fan_triangulate(part).triangles;
  std::unordered_map<uint64_t, uint32_t> midpoint;
  auto split = [&](uint32_t a, uint32_t b) -> std::optional<uint32_t> {
    if (!on_boundary[a] || !on_boundary[b] || on_rim(a, b) || on_rim(b, a)) return std::nullopt;
    const auto [it, added] = midpoint.emplace(undirected_edge_key(a, b), 0);
    if (added) it->second = add_vertex((part.positions[a] + part.positions[b]) * 0.5);
    return it->second;
  };
  std::vector<uint32_t> corners;
  for (size_t t = 0; t < front.size(); ++t) {
    corners.clear();
    for (int i = 3; i-- > 0;) {  // the triangle reversed, split edges' midpoints in
      const uint32_t a = front[t][i], b = front[t][(i + 2) % 3];
      corners.push_back(back_vertex[a]);
      if (const std::optional<uint32_t> m = split(a, b)) corners.push_back(*m);
    }
    if (corners.size() == 3 && front.size() > 1) {
      // A front triangle's mirror, as flat as it may be (a CAD export's sliver): the map
      // takes it as it takes the front's.
      back.triangles.push_back({corners[0], corners[1], corners[2]});
    } else {  // a fan around the centroid, in the triangle's plane (a lone triangle too: two
              // faces on three vertices cannot be mapped)
      Vec3 centroid{0, 0, 0};
      for (uint32_t v : corners) centroid += position(v);
      const uint32_t apex = add_vertex(centroid * (1.0 / static_cast<double>(corners.size())));
      for (size_t i = 0; i < corners.size(); ++i) {
        const Triangle fan{apex, corners[i], corners[(i + 1) % corners.size()]};
        if (!has_area(position(fan[0]), position(fan[1]), position(fan[2]))) return std::nullopt;
        back.triangles.push_back(fan);
      }
    }
    if (stop && t % 4096 == 0) stop->check();
  }
  return back;
}

}  // namespace

bool is_open_sphere(const TopologyReport& topology) {
  const std::vector<ValidationFailure> failures = mapping_failures(topology);
  return failures.size() == 1 && failures.front().check == "boundary" &&
         topology.euler_characteristic + static_cast<long long>(topology.boundary_loops) == 2;
}

bool is_open_disc(const TopologyReport& topology) {
  return is_open_sphere(topology) && topology.boundary_loops == 1;
}

SheetDoubling double_open_sheets(PolygonMesh& mesh, const StopCheck* stop) {
  SheetDoubling result;
  const std::vector<MeshPart> parts = connected_parts(mesh, stop);
  for (const MeshPart& part : parts) {
    const TopologyReport topology = analyze_topology(part.mesh, stop);
    if (!is_open_disc(topology)) continue;
    std::optional<Back> back = back_of(part.mesh, stop);
    if (!back) continue;
    // The part closed by its back must map: checked, not assumed.
    PolygonMesh closed = part.mesh;
    closed.positions.insert(closed.positions.end(), back->positions.begin(), back->positions.end());
    for (const Triangle& t : back->triangles) closed.add_face(t);
    if (!mapping_failures(analyze_topology(closed, stop)).empty()) continue;
    // Appended to the whole: the part's vertices by their ids there, the new ones after.
    const uint32_t n = static_cast<uint32_t>(part.mesh.vertex_count());
    const uint32_t first_new = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), back->positions.begin(), back->positions.end());
    for (const Triangle& t : back->triangles) {
      Triangle whole;
      for (int k = 0; k < 3; ++k) whole[k] = t[k] < n ? part.vertex[t[k]] : first_new + t[k] - n;
      mesh.add_face(whole);
    }
    ++result.sheets_doubled;
    result.faces_added += back->triangles.size();
    result.vertices_added += back->positions.size();
  }
  return result;
}

}  // namespace spheremap
