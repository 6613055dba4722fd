#include "core/mesh/mesh.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace spheremap {

void PolygonMesh::add_face(std::span<const uint32_t> corners) {
  indices.insert(indices.end(), corners.begin(), corners.end());
  offsets.push_back(static_cast<uint32_t>(indices.size()));
}

namespace {

uint64_t edge_key(uint32_t a, uint32_t b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

// Picks, per polygon, the first apex whose diagonals are all new edges.
std::vector<uint32_t> choose_apexes(const PolygonMesh& mesh, size_t& conflicts) {
  std::vector<uint32_t> apex(mesh.face_count(), 0);
  if (mesh.is_triangle_mesh()) return apex;
  std::unordered_set<uint64_t> edges;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      edges.insert(edge_key(face[k], face[(k + 1) % face.size()]));
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    const size_t d = face.size();
    if (d == 3) continue;
    bool found = false;
    for (size_t a = 0; a < d && !found; ++a) {
      found = true;
      for (size_t k = 2; k + 1 < d && found; ++k)
        found = !edges.count(edge_key(face[a], face[(a + k) % d]));
      if (found) apex[f] = static_cast<uint32_t>(a);
    }
    if (!found) ++conflicts;
    for (size_t k = 2; k + 1 < d; ++k)
      edges.insert(edge_key(face[apex[f]], face[(apex[f] + k) % d]));
  }
  return apex;
}

}  // namespace

uint32_t face_of_slot(const PolygonMesh& mesh, uint32_t slot) {
  return static_cast<uint32_t>(std::upper_bound(mesh.offsets.begin(), mesh.offsets.end(), slot) -
                               mesh.offsets.begin() - 1);
}

uint32_t vertex_before(const PolygonMesh& mesh, uint32_t slot) {
  const uint32_t f = face_of_slot(mesh, slot);
  const uint32_t size = mesh.offsets[f + 1] - mesh.offsets[f];
  return mesh.indices[mesh.offsets[f] + (slot - mesh.offsets[f] + size - 1) % size];
}

FanTriangulation fan_triangulate(const PolygonMesh& mesh) {
  FanTriangulation fan;
  const std::vector<uint32_t> apex = choose_apexes(mesh, fan.conflicting_faces);
  fan.triangles.reserve(mesh.indices.size() - 2 * mesh.face_count());
  fan.triangle_face.reserve(fan.triangles.capacity());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    const size_t d = face.size(), a = apex[f];
    for (size_t k = 1; k + 1 < d; ++k) {
      fan.triangles.push_back({face[a], face[(a + k) % d], face[(a + k + 1) % d]});
      fan.triangle_face.push_back(static_cast<uint32_t>(f));
    }
  }
  return fan;
}

PolygonMesh apex_first(const PolygonMesh& mesh) {
  return apex_first(mesh, mesh);
}

PolygonMesh apex_first(const PolygonMesh& mesh, const PolygonMesh& decided_on) {
  PolygonMesh out = mesh;
  if (mesh.is_triangle_mesh()) return out;
  size_t conflicting = 0;
  const std::vector<uint32_t> apex = choose_apexes(decided_on, conflicting);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    const size_t d = face.size();
    for (size_t k = 0; k < d; ++k) out.indices[mesh.offsets[f] + k] = face[(apex[f] + k) % d];
  }
  return out;
}

VertexTriangles vertex_triangles(std::span<const Triangle> triangles, size_t vertex_count) {
  VertexTriangles vt;
  vt.offsets.assign(vertex_count + 1, 0);
  for (const Triangle& t : triangles)
    for (uint32_t v : t) ++vt.offsets[v + 1];
  for (size_t v = 0; v < vertex_count; ++v) vt.offsets[v + 1] += vt.offsets[v];
  vt.triangles.resize(vt.offsets.back());
  std::vector<uint32_t> cursor(vt.offsets.begin(), vt.offsets.end() - 1);
  for (uint32_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t]) vt.triangles[cursor[v]++] = t;
  return vt;
}

// On the mesh centred and scaled: each term is then of the size of the mesh, not of its
// distance from the origin (a mesh far from the origin summed terms of 1e16 into a volume
// of 4e-9, and got its orientation by chance), and no cube overflows or underflows.
double signed_volume(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  const std::vector<Vec3> p = centered_and_scaled(positions);
  double six_volume = 0;
  for (const Triangle& t : triangles) six_volume += dot(p[t[0]], cross(p[t[1]], p[t[2]]));
  return six_volume / 6.0;
}

bool volume_runs_inward(double six_volume, double twice_area) {
  constexpr double kNoVolume = 1e-9;
  return six_volume < -kNoVolume * twice_area;
}

bool runs_inward(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  const std::vector<Vec3> p = centered_and_scaled(positions);
  double six_volume = 0, twice_area = 0;
  for (const Triangle& t : triangles) {
    six_volume += dot(p[t[0]], cross(p[t[1]], p[t[2]]));
    twice_area += norm(cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]));
  }
  return volume_runs_inward(six_volume, twice_area);
}

Vec3 bounding_box_center(std::span<const Vec3> positions) {
  if (positions.empty()) return {};
  Vec3 lo = positions[0], hi = positions[0];
  for (const Vec3& p : positions) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return 0.5 * lo + 0.5 * hi;  // halves first: lo + hi may overflow
}

namespace {

double largest_coordinate(std::span<const Vec3> positions) {
  double largest = 0;
  for (const Vec3& p : positions)
    largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return largest;
}

// The exponent e with largest / 2^e in [1, 2) (0 when there is nothing to scale).
int exponent_of(double largest) {
  return largest > 0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
}

// p * 2^-exponent. A product with a power of two is rounded once, as ldexp is, so the two
// agree, and it costs far less than three ldexp calls (the topology check moves every
// corner of every face: ~100M instructions on scorpion); ldexp is left for factors no
// double holds.
Vec3 scaled(const Vec3& p, int exponent) {
  if (exponent >= -1000 && exponent <= 1000) return p * std::ldexp(1.0, -exponent);
  return {std::ldexp(p.x, -exponent), std::ldexp(p.y, -exponent), std::ldexp(p.z, -exponent)};
}

}  // namespace

// Powers of two (exact, and no overflow or underflow on the way: 1 / 1e-310 is not a
// double), first so that the largest coordinate is about 1, then so that the centred mesh
// is: coordinates from 1e-300 to 1e300 come out the same.
UnitFrame unit_frame(std::span<const Vec3> positions) {
  UnitFrame frame;
  frame.exponent = exponent_of(largest_coordinate(positions));
  std::vector<Vec3> p(positions.size());
  for (size_t k = 0; k < p.size(); ++k) p[k] = scaled(positions[k], frame.exponent);
  frame.center = bounding_box_center(p);
  double largest = 0;
  for (const Vec3& q : p)
    largest = std::max({largest, std::abs(q.x - frame.center.x), std::abs(q.y - frame.center.y),
                        std::abs(q.z - frame.center.z)});
  frame.exponent2 = exponent_of(largest);
  return frame;
}

Vec3 UnitFrame::apply(const Vec3& p) const {
  return scaled(scaled(p, exponent) - center, exponent2);
}

double UnitFrame::length_in_input_units(double length) const {
  return std::ldexp(std::ldexp(length, exponent2), exponent);
}

void center_and_scale(std::span<Vec3> positions) {
  const UnitFrame frame = unit_frame(positions);
  for (Vec3& p : positions) p = frame.apply(p);
}

std::vector<Vec3> centered_and_scaled(std::span<const Vec3> positions) {
  std::vector<Vec3> copy(positions.begin(), positions.end());
  center_and_scale(copy);
  return copy;
}

}  // namespace spheremap
