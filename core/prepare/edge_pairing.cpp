#include "core/prepare/edge_pairing.h"

#include <algorithm>
#include <cmath>

#include "core/prepare/hole_filling.h"  // undirected_edge_key

namespace spheremap {
namespace {

// Two faces closer in angle than this (radians) lie on each other: no order between them.
constexpr double kSameAngle = 1e-9;

// How pair_edge matches: every face (as many each way), the other match of four, or the
// faces that match and each other face let go.
enum class Match { kAll, kOther, kLetGo };

// The pairs of one edge's faces (`begin`..`end` in `corners`), or nothing.
bool pair_edge(const PolygonMesh& mesh, const EdgeCorner* begin, const EdgeCorner* end, Match match,
               std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
  const size_t k = static_cast<size_t>(end - begin);
  if (match == Match::kLetGo ? k < 3 : k < 4 || k % 2 != 0) return false;
  std::vector<uint32_t> far;
  for (const EdgeCorner* c = begin; c != end; ++c) far.push_back(c->far);
  const std::vector<double> angles = angles_about_edge(
      mesh, static_cast<uint32_t>(begin->edge >> 32), static_cast<uint32_t>(begin->edge), far);
  if (angles.empty()) return false;
  std::vector<std::pair<double, const EdgeCorner*>> by_angle;
  for (size_t i = 0; i < k; ++i) by_angle.push_back({angles[i], begin + i});
  std::sort(by_angle.begin(), by_angle.end(),
            [](const auto& p, const auto& q) { return p.first < q.first; });
  const auto gap_after = [&](size_t i) {
    return i + 1 < k ? by_angle[i + 1].first - by_angle[i].first
                     : by_angle[0].first + 2 * M_PI - by_angle[i].first;
  };
  for (size_t i = 0; i < k; ++i) {
    if (gap_after(i) > kSameAngle) continue;
    // Two faces on each other, running opposite ways, apart from the rest: two solids
    // stacked face to face, each with its own face on the plane they share (a CAD
    // assembly exported as one mesh: barkour's leg, a pad on a plate). The wedge of no
    // width between them is taken as empty, so each is paired within its own solid: the
    // face running a -> b (its solid toward smaller angles) first. Any other tie (faces
    // running one way, three on each other) has no order.
    const size_t j = (i + 1) % k;
    if (by_angle[i].second->forward == by_angle[j].second->forward ||
        !(gap_after((i + k - 1) % k) > kSameAngle) || !(gap_after(j) > kSameAngle))
      return false;
    if (!by_angle[i].second->forward) std::swap(by_angle[i].second, by_angle[j].second);
    ++i;
  }
  // A face running b -> a has its solid toward larger angles, one running a -> b toward
  // smaller: read by angle, the first opens a wedge and the second closes it, as brackets.
  // From the angle after the deepest point of the running count, the faces match as
  // brackets do; where directions alternate, each pair bounds one solid wedge, elsewhere
  // (faces through each other) the pairs nest.
  long long depth = 0, lowest = 0;
  size_t start = 0;
  for (size_t i = 0; i < k; ++i) {
    depth += by_angle[i].second->forward ? -1 : 1;
    if (depth < lowest) lowest = depth, start = i + 1;
  }
  if (depth != 0 && match != Match::kLetGo) return false;
  // Letting go, a closing face with no open wedge before it and the opening faces left at
  // the end stay unpaired (partnered with nothing at this edge).
  std::vector<const EdgeCorner*> open;
  for (size_t i = 0; i < k; ++i) {
    const EdgeCorner* c = by_angle[(start + i) % k].second;
    if (!c->forward) {
      open.push_back(c);
      continue;
    }
    if (open.empty()) continue;
    const EdgeCorner* back = open.back();
    open.pop_back();
    pairs.push_back({back->face, c->face});
    pairs.push_back({c->face, back->face});
  }
  // Four faces: the other match of each with one running the other way.
  if (match == Match::kOther) {
    if (k != 4) return false;
    std::swap(pairs[0].second, pairs[2].second);
    pairs[1] = {pairs[0].second, pairs[0].first};
    pairs[3] = {pairs[2].second, pairs[2].first};
  }
  return true;
}

EdgePairs pair_faces(const PolygonMesh& mesh, Match match, const StopCheck* stop) {
  const std::vector<EdgeCorner> corners = sorted_edge_corners(mesh, stop);
  EdgePairs pairs;
  std::vector<std::pair<uint32_t, uint32_t>> edge_pairs;
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    if (j - i <= 2) continue;
    edge_pairs.clear();
    // A face running along the edge twice (a corner repeated) has no one side there.
    bool twice = false;
    for (size_t m = i + 1; m < j; ++m) twice |= corners[m].face == corners[m - 1].face;
    if (!twice && pair_edge(mesh, &corners[i], &corners[j], match, edge_pairs))
      pairs.emplace(corners[i].edge, edge_pairs);
  }
  return pairs;
}

}  // namespace

EdgePairs pair_faces_at_non_manifold_edges(const PolygonMesh& mesh, bool other,
                                           const StopCheck* stop) {
  return pair_faces(mesh, other ? Match::kOther : Match::kAll, stop);
}

EdgePairs pair_faces_letting_go_of_the_rest(const PolygonMesh& mesh, const StopCheck* stop) {
  return pair_faces(mesh, Match::kLetGo, stop);
}

std::vector<EdgeCorner> sorted_edge_corners(const PolygonMesh& mesh, const StopCheck* stop) {
  std::vector<EdgeCorner> corners;
  corners.reserve(mesh.indices.size());
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t begin = mesh.offsets[f], size = mesh.offsets[f + 1] - begin;
    for (uint32_t i = 0; i < size; ++i) {
      const uint32_t u = mesh.indices[begin + i], v = mesh.indices[begin + (i + 1) % size];
      if (u != v)
        corners.push_back(
            {undirected_edge_key(u, v), f, mesh.indices[begin + (i + 2) % size], u < v});
    }
  }
  if (stop) stop->check();
  std::sort(corners.begin(), corners.end());
  return corners;
}

UnionFind manifold_sheets(std::span<const EdgeCorner> corners, uint32_t faces) {
  UnionFind sheets(faces);
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    if (j - i == 2) sheets.unite(corners[i].face, corners[i + 1].face);
  }
  return sheets;
}

std::vector<double> angles_about_edge(const PolygonMesh& mesh, uint32_t a, uint32_t b,
                                      std::span<const uint32_t> far) {
  const Vec3 origin = mesh.positions[a];
  const Vec3 axis = mesh.positions[b] - origin;
  const double length = norm(axis);
  if (!(length > 0) || far.empty()) return {};
  const Vec3 d = axis * (1.0 / length);
  auto across = [&](uint32_t v) {
    const Vec3 e = mesh.positions[v] - origin;
    return e - d * dot(e, d);
  };
  const Vec3 x0 = across(far[0]);
  if (!(norm(x0) > 1e-12 * length)) return {};
  const Vec3 x = x0 * (1.0 / norm(x0)), y = cross(d, x);
  std::vector<double> angles;
  for (uint32_t v : far) {
    const Vec3 e = across(v);
    if (!(norm(e) > 1e-12 * length)) return {};
    angles.push_back(std::atan2(dot(e, y), dot(e, x)));
  }
  return angles;
}

uint32_t paired_face(const EdgePairs& pairs, uint64_t edge, uint32_t face) {
  const auto it = pairs.find(edge);
  if (it == pairs.end()) return face;
  for (const auto& [from, to] : it->second)
    if (from == face) return to;
  return face;
}

}  // namespace spheremap
