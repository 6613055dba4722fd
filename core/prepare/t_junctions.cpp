#include "core/prepare/t_junctions.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/mesh/half_edge_ends.h"
#include "core/prepare/hole_filling.h"

namespace spheremap {
namespace {

struct BoundaryEdge {
  uint32_t face, corner, a, b;
};

// The fan apex of a face of `size` corners with `splits` (by corner), as an index into the
// polygon with the inserted corners (see split_face); -1 when none is off every split
// edge's line: an original corner on no split edge, else the one vertex inserted into an
// edge split once.
int fan_apex(size_t size, std::span<const EdgeSplit> splits) {
  std::vector<char> on_split(size, 0);
  for (const EdgeSplit& s : splits) on_split[s.corner] = on_split[(s.corner + 1) % size] = 1;
  int position = 0;
  size_t next = 0;
  int single = -1;
  for (uint32_t k = 0; k < size; ++k) {
    if (!on_split[k]) return position;
    ++position;
    if (next < splits.size() && splits[next].corner == k) {
      if (single < 0 && splits[next].inserted.size() == 1) single = position;
      position += static_cast<int>(splits[next++].inserted.size());
    }
  }
  return single;
}

uint64_t cell_key(int64_t x, int64_t y, int64_t z) {
  uint64_t h = 1469598103934665603ull;
  for (int64_t c : {x, y, z}) h = (h ^ static_cast<uint64_t>(c)) * 1099511628211ull;
  return h;
}

}  // namespace

std::vector<EdgeSplit> find_t_junctions(const PolygonMesh& faces,
                                        const std::vector<Vec3>& positions, StopCheck* stop) {
  // Boundary edges are those of one face.
  const HalfEdgeEnds ends(faces);
  std::vector<BoundaryEdge> boundary;
  for (uint32_t f = 0; f < faces.face_count(); ++f) {
    const auto face = faces.face(f);
    for (uint32_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      if (a != b && ends.faces_beside(a, b) == 1) boundary.push_back({f, k, a, b});
    }
  }
  if (stop) stop->check();
  if (boundary.size() < 3) return {};

  // Boundary vertices, hashed in a grid of about the mean boundary edge's length.
  Vec3 low = positions[boundary.front().a], high = low;
  double total_length = 0;
  std::vector<uint32_t> vertices;
  for (const BoundaryEdge& e : boundary) {
    vertices.push_back(e.a), vertices.push_back(e.b);
    total_length += norm(positions[e.b] - positions[e.a]);
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  for (uint32_t v : vertices) {
    const Vec3& p = positions[v];
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  const double diagonal = norm(high - low);
  const double tolerance = kTJunctionTolerance * diagonal;
  if (!(diagonal > 0) || !std::isfinite(diagonal)) return {};
  const double cell = std::max(total_length / static_cast<double>(boundary.size()), 4 * tolerance);
  auto cell_of = [&](const Vec3& p, int axis) {
    return static_cast<int64_t>(std::floor((p[axis] - low[axis]) / cell));
  };
  std::vector<std::pair<uint64_t, uint32_t>> grid;  // (cell key, vertex), sorted
  grid.reserve(vertices.size());
  for (uint32_t v : vertices) {
    const Vec3& p = positions[v];
    grid.push_back({cell_key(cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)), v});
  }
  std::sort(grid.begin(), grid.end());
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> cells;  // key -> grid range
  cells.reserve(grid.size());
  for (uint32_t k = 0; k < grid.size(); ++k) {
    auto [it, added] = cells.emplace(grid[k].first, std::pair{k, k + 1});
    if (!added) it->second.second = k + 1;
  }

  // Per boundary edge, the boundary vertices on it, by their place along it.
  std::vector<EdgeSplit> splits;
  std::vector<std::pair<double, uint32_t>> found;
  size_t visits = 0;
  for (const BoundaryEdge& e : boundary) {
    const Vec3 a = positions[e.a], ab = positions[e.b] - a;
    const double length = norm(ab);
    if (!(length > 2 * tolerance)) continue;
    found.clear();
    auto visit = [&](int64_t x, int64_t y, int64_t z) {
      const auto range = cells.find(cell_key(x, y, z));
      if (range == cells.end()) return;
      for (uint32_t k = range->second.first; k < range->second.second; ++k) {
        const uint32_t t = grid[k].second;
        if (t == e.a || t == e.b) continue;
        const Vec3 at = positions[t] - a;
        const double along = dot(at, ab) / (length * length);
        if (!(along > 0 && along < 1)) continue;
        if (norm(at - ab * along) > tolerance) continue;
        if (norm(at) <= tolerance || norm(positions[t] - positions[e.b]) <= tolerance) continue;
        found.push_back({along, t});
      }
    };
    // The cells of the edge's box (widened by the tolerance) when few (a short edge), else
    // the 27 around each of samples a cell apart along it (a long slanted edge).
    const Vec3 b = positions[e.b];
    int64_t from[3], to[3];
    size_t box = 1;
    for (int axis = 0; axis < 3; ++axis) {
      from[axis] = cell_of(Vec3{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)} -
                               Vec3{tolerance, tolerance, tolerance},
                           axis);
      to[axis] = cell_of(Vec3{std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)} +
                             Vec3{tolerance, tolerance, tolerance},
                         axis);
      box *= static_cast<size_t>(std::min<int64_t>(to[axis] - from[axis] + 1, 1 << 20));
    }
    const size_t samples = static_cast<size_t>(std::ceil(length / cell)) + 1;
    const size_t cost = std::min(box, 27 * samples);
    visits += cost;
    if (stop) stop->tick(cost);
    if (visits > kMaxZipCellVisits) return {};
    if (box <= 27 * samples) {
      for (int64_t x = from[0]; x <= to[0]; ++x)
        for (int64_t y = from[1]; y <= to[1]; ++y)
          for (int64_t z = from[2]; z <= to[2]; ++z) visit(x, y, z);
    } else {
      for (size_t s = 0; s < samples; ++s) {
        const Vec3 p = a + ab * (static_cast<double>(s) / static_cast<double>(samples - 1));
        const int64_t x = cell_of(p, 0), y = cell_of(p, 1), z = cell_of(p, 2);
        for (int64_t dx = -1; dx <= 1; ++dx)
          for (int64_t dy = -1; dy <= 1; ++dy)
            for (int64_t dz = -1; dz <= 1; ++dz) visit(x + dx, y + dy, z + dz);
      }
    }
    if (found.empty()) continue;
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    EdgeSplit split{e.face, e.corner, {}};
    for (const auto& [along, t] : found)
      if (split.inserted.empty() || split.inserted.back() != t) split.inserted.push_back(t);
    splits.push_back(std::move(split));
  }
  if (splits.empty()) return {};
  std::sort(splits.begin(), splits.end(), [](const EdgeSplit& x, const EdgeSplit& y) {
    return x.face != y.face ? x.face < y.face : x.corner < y.corner;
  });

  // Faces whose fan would have a flat triangle keep their edges whole.
  std::vector<char> keep(splits.size(), 1);
  for (size_t s = 0; s < splits.size();) {
    size_t run = s;
    while (run < splits.size() && splits[run].face == splits[s].face) ++run;
    const std::span<const EdgeSplit> of_face(splits.data() + s, run - s);
    if (fan_apex(faces.face_size(splits[s].face), of_face) < 0)
      std::fill(keep.begin() + s, keep.begin() + run, 0);
    s = run;
  }
  // Each piece must meet exactly one other edge; dropping a split can orphan another's
  // pieces, so this repeats until nothing changes (bounded: each round drops one or more).
  auto pieces = [&](const EdgeSplit& s, auto&& visit) {
    const auto face = faces.face(s.face);
    uint32_t from = face[s.corner];
    for (uint32_t t : s.inserted) visit(undirected_edge_key(from, t)), from = t;
    visit(undirected_edge_key(from, face[(s.corner + 1) % face.size()]));
  };
  bool stable = false;
  for (size_t round = 0; round < 16 && !stable; ++round) {
    if (stop) stop->check();
    // Each edge's face count with the kept splits made, for the edges they touch.
    std::unordered_map<uint64_t, uint32_t> touched;
    auto count = [&](uint64_t key) -> uint32_t& {
      const auto [it, added] = touched.try_emplace(key, 0);
      if (added) {
        const uint32_t a = static_cast<uint32_t>(key >> 32), b = static_cast<uint32_t>(key);
        it->second = static_cast<uint32_t>(a == b ? ends.count(a, a) : ends.faces_beside(a, b));
      }
      return it->second;
    };
    for (size_t s = 0; s < splits.size(); ++s) {
      if (!keep[s]) continue;
      const auto face = faces.face(splits[s].face);
      --count(
          undirected_edge_key(face[splits[s].corner], face[(splits[s].corner + 1) % face.size()]));
      pieces(splits[s], [&](uint64_t key) { ++count(key); });
    }
    bool dropped = false;
    for (size_t s = 0; s < splits.size(); ++s) {
      if (!keep[s]) continue;
      bool closes = true;
      pieces(splits[s], [&](uint64_t key) { closes = closes && count(key) == 2; });
      if (!closes) keep[s] = 0, dropped = true;
    }
    stable = !dropped;
  }
  if (!stable) return {};  // a chain of dependent splits: left as it is
  std::vector<EdgeSplit> kept;
  for (size_t s = 0; s < splits.size(); ++s)
    if (keep[s]) kept.push_back(std::move(splits[s]));
  return kept;
}

bool split_face(std::span<const uint32_t> welded_face, std::span<const uint32_t> input_face,
                std::span<const EdgeSplit> splits, const std::vector<uint32_t>& input_of_welded,
                std::vector<Triangle>& welded_out, std::vector<Triangle>& input_out) {
  const int apex = fan_apex(welded_face.size(), splits);
  if (apex < 0) return false;
  std::vector<uint32_t> welded, input;
  size_t next = 0;
  for (uint32_t k = 0; k < welded_face.size(); ++k) {
    welded.push_back(welded_face[k]), input.push_back(input_face[k]);
    if (next < splits.size() && splits[next].corner == k)
      for (uint32_t t : splits[next++].inserted)
        welded.push_back(t), input.push_back(input_of_welded[t]);
  }
  std::rotate(welded.begin(), welded.begin() + apex, welded.end());
  std::rotate(input.begin(), input.begin() + apex, input.end());
  for (size_t k = 1; k + 1 < welded.size(); ++k) {
    welded_out.push_back({welded[0], welded[k], welded[k + 1]});
    input_out.push_back({input[0], input[k], input[k + 1]});
  }
  return true;
}

}  // namespace spheremap
