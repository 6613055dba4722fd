#include "core/mesh/topology.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/input_error.h"
#include "core/mesh/union_find.h"

namespace spheremap {
namespace {

struct HalfEdge {
  uint32_t from, to;
  uint32_t corner_from, corner_to;  // positions in mesh.indices
  uint64_t key() const {
    return (static_cast<uint64_t>(std::min(from, to)) << 32) | std::max(from, to);
  }
};

// Every half-edge, grouped by undirected edge: bucketed by the smaller vertex (a counting
// sort), then each vertex's few edges sorted by the larger one. A comparison sort of all
// half-edges was half of the topology check's time.
std::vector<HalfEdge> half_edges(const PolygonMesh& mesh) {
  const size_t n = mesh.vertex_count();
  auto for_each_half_edge = [&](auto&& visit) {
    for (size_t f = 0; f < mesh.face_count(); ++f) {
      const uint32_t begin = mesh.offsets[f], size = mesh.offsets[f + 1] - begin;
      for (uint32_t k = 0; k < size; ++k) {
        const uint32_t a = begin + k, b = begin + (k + 1) % size;
        if (mesh.indices[a] != mesh.indices[b])
          visit(HalfEdge{mesh.indices[a], mesh.indices[b], a, b});
      }
    }
  };
  std::vector<uint32_t> start(n + 1, 0);
  for_each_half_edge([&](const HalfEdge& h) { ++start[std::min(h.from, h.to) + 1]; });
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<HalfEdge> edges(start[n]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for_each_half_edge([&](const HalfEdge& h) { edges[fill[std::min(h.from, h.to)]++] = h; });
  for (size_t v = 0; v < n; ++v)
    std::sort(edges.begin() + start[v], edges.begin() + start[v + 1],
              [](const HalfEdge& x, const HalfEdge& y) { return x.key() < y.key(); });
  return edges;
}

// A face uses a vertex twice: pairwise for the usual small faces (no allocation per face).
bool repeats_a_vertex(std::span<const uint32_t> face) {
  if (face.size() > 16) {
    std::vector<uint32_t> sorted(face.begin(), face.end());
    std::sort(sorted.begin(), sorted.end());
    return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
  }
  for (size_t i = 0; i < face.size(); ++i)
    for (size_t j = i + 1; j < face.size(); ++j)
      if (face[i] == face[j]) return true;
  return false;
}

void count_faces(const PolygonMesh& mesh, TopologyReport& r) {
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    ++r.face_sizes[face.size()];
    if (repeats_a_vertex(face)) ++r.faces_with_repeated_vertices;
  }
}

void measure_geometry(const PolygonMesh& mesh, TopologyReport& r) {
  std::vector<char> used(mesh.vertex_count(), 0);
  for (uint32_t v : mesh.indices) used[v] = 1;
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    r.vertices += used[v];
    const Vec3& p = mesh.positions[v];
    if (!is_finite(p)) {
      ++r.non_finite_vertices;
      continue;
    }
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  if (r.non_finite_vertices || mesh.vertex_count() == 0) return;
  // In the unit frame (center_and_scale's): far from the origin the volume's terms would
  // cancel to noise, and at 1e200 areas and volumes overflow (every face zero-area).
  // Each vertex moved once (a face corner is ~6 per vertex).
  const UnitFrame frame = unit_frame(mesh.positions);
  const double tiny_area = 1e-14 * squared_norm(frame.apply(hi) - frame.apply(lo));
  const std::vector<Vec3> unit = centered_and_scaled(mesh.positions);
  double six_volume = 0, twice_area = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    Vec3 area_vector;
    const Vec3& a = unit[face[0]];
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      const Vec3& b = unit[face[k]];
      const Vec3& c = unit[face[k + 1]];
      const Vec3 fan_area = cross(b - a, c - a);
      area_vector += fan_area;
      twice_area += norm(fan_area);
      six_volume += dot(a, cross(b, c));
    }
    if (0.5 * norm(area_vector) <= tiny_area) ++r.zero_area_faces;
  }
  r.signed_volume = six_volume / 6.0;
  r.inward = volume_runs_inward(six_volume, twice_area);
}

// Edges, boundary loops, non-manifold edges, orientation, and vertex fans: corners
// of a vertex joined across the edges they share; more than one class = pinched vertex.
void analyze_edges(const PolygonMesh& mesh, TopologyReport& r) {
  const std::vector<HalfEdge> edges = half_edges(mesh);
  UnionFind fans(mesh.indices.size());
  UnionFind boundary(mesh.vertex_count());
  std::vector<char> on_boundary(mesh.vertex_count(), 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].key() == edges[i].key()) ++j;
    ++r.edges;
    const size_t count = j - i;
    if (count == 1) {
      ++r.boundary_edges;
      boundary.unite(edges[i].from, edges[i].to);
      on_boundary[edges[i].from] = on_boundary[edges[i].to] = 1;
    } else if (count > 2) {
      ++r.non_manifold_edges;
    } else if (edges[i].from == edges[i + 1].from) {
      ++r.inconsistent_edges;
    }
    for (size_t k = i + 1; k < j; ++k) {
      // Corners at the same vertex are joined, whichever direction each half-edge runs.
      auto corner_at = [&](const HalfEdge& h, uint32_t v) {
        return h.from == v ? h.corner_from : h.corner_to;
      };
      fans.unite(corner_at(edges[i], edges[i].from), corner_at(edges[k], edges[i].from));
      fans.unite(corner_at(edges[i], edges[i].to), corner_at(edges[k], edges[i].to));
    }
    i = j;
  }
  std::vector<uint32_t> first_fan(mesh.vertex_count(), UINT32_MAX);
  std::vector<char> pinched(mesh.vertex_count(), 0);
  for (uint32_t c = 0; c < mesh.indices.size(); ++c) {
    const uint32_t v = mesh.indices[c], fan = fans.find(c);
    if (first_fan[v] == UINT32_MAX)
      first_fan[v] = fan;
    else if (first_fan[v] != fan)
      pinched[v] = 1;
  }
  r.non_manifold_vertices = static_cast<size_t>(std::count(pinched.begin(), pinched.end(), 1));
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (on_boundary[v] && boundary.find(v) == v) ++r.boundary_loops;
}

void find_components(const PolygonMesh& mesh, TopologyReport& r) {
  UnionFind sets(mesh.vertex_count());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  std::map<uint32_t, std::pair<size_t, size_t>> sizes;  // root -> (vertices, faces)
  std::vector<char> used(mesh.vertex_count(), 0);
  for (uint32_t v : mesh.indices) used[v] = 1;
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (used[v]) ++sizes[sets.find(v)].first;
  for (size_t f = 0; f < mesh.face_count(); ++f) ++sizes[sets.find(mesh.face(f)[0])].second;
  std::vector<std::pair<size_t, size_t>> list;
  for (auto& [root, size] : sizes) list.push_back(size);
  std::sort(list.begin(), list.end(), std::greater<>());
  for (auto [v, f] : list) {
    r.component_vertices.push_back(v);
    r.component_faces.push_back(f);
  }
}

std::string list_sizes(const std::vector<size_t>& sizes) {
  std::string s;
  for (size_t i = 0; i < sizes.size() && i < 8; ++i)
    s += (i ? ", " : "") + std::to_string(sizes[i]);
  if (sizes.size() > 8) s += ", ...";
  return s;
}

}  // namespace

long long TopologyReport::genus() const {
  if (!closed() || !manifold() || inconsistent_edges || component_vertices.size() != 1) return -1;
  return (2 - euler_characteristic) / 2;
}

TopologyReport analyze_topology(const PolygonMesh& mesh, const StopCheck* stop) {
  const auto ask = [stop] {
    if (stop) stop->check();
  };
  TopologyReport r;
  r.faces = mesh.face_count();
  count_faces(mesh, r);
  ask();
  measure_geometry(mesh, r);
  ask();
  analyze_edges(mesh, r);
  ask();
  find_components(mesh, r);
  r.euler_characteristic = static_cast<long long>(r.vertices) - static_cast<long long>(r.edges) +
                           static_cast<long long>(r.faces);
  return r;
}

std::vector<ValidationFailure> mapping_failures(const TopologyReport& r) {
  std::vector<ValidationFailure> out;
  auto n = [](size_t v) { return std::to_string(v); };
  // "1 boundary loop", "2 boundary loops": a count with its noun in the right number.
  auto count = [](size_t v, const char* one, const char* many) {
    return std::to_string(v) + " " + (v == 1 ? one : many);
  };
  if (r.faces == 0) out.push_back({"empty", "mesh has no faces"});
  if (r.non_finite_vertices)
    out.push_back({"non_finite", count(r.non_finite_vertices, "vertex has", "vertices have") +
                                     " non-finite coordinates"});
  if (r.faces_with_repeated_vertices)
    out.push_back(
        {"repeated_vertex", count(r.faces_with_repeated_vertices, "face uses", "faces use") +
                                " the same vertex twice"});
  if (r.non_manifold_edges)
    out.push_back({"non_manifold_edge", count(r.non_manifold_edges, "edge is", "edges are") +
                                            " shared by more than 2 faces"});
  if (r.boundary_edges)
    out.push_back(
        {"boundary", "mesh has " + count(r.boundary_loops, "boundary loop", "boundary loops") +
                         " (" + count(r.boundary_edges, "boundary edge", "boundary edges") +
                         "); spherical mapping needs a closed surface"});
  if (r.non_manifold_vertices)
    out.push_back({"non_manifold_vertex",
                   count(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") +
                       " (the faces around each form more than one fan)"});
  if (r.inconsistent_edges)
    out.push_back({"orientation", count(r.inconsistent_edges, "edge has", "edges have") +
                                      " faces on both sides running the same way "
                                      "(inconsistent orientation)"});
  if (r.component_vertices.size() > 1)
    out.push_back({"components",
                   "mesh has " + n(r.component_vertices.size()) +
                       " connected components (vertices: " + list_sizes(r.component_vertices) +
                       "); spherical mapping needs exactly one",
                   {"largest_component", "true", "maps only the part with the most faces"}});
  if (out.empty() && r.genus() != 0)
    out.push_back({"genus", "mesh has genus " + std::to_string(r.genus()) +
                                " (Euler characteristic " + std::to_string(r.euler_characteristic) +
                                "); spherical mapping needs genus 0"});
  if (out.empty() && r.vertices < 4)
    out.push_back({"too_small", "mesh has " + n(r.vertices) + " vertices; at least 4 are needed"});
  return out;
}

void require_mappable(const TopologyReport& report) {
  require_none(mapping_failures(report));
}

void require_none(const std::vector<ValidationFailure>& failures) {
  if (failures.empty()) return;
  std::string message = failures[0].message;
  Fix fix = failures[0].fix;
  for (size_t i = 1; i < failures.size(); ++i) {
    message += "; also " + failures[i].message;
    if (fix.empty()) fix = failures[i].fix;
  }
  throw InputError(failures[0].check, message, fix);
}

}  // namespace spheremap
