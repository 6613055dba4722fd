#include "core/mesh/triangle_tree.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace spheremap {

Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  // denom = |ab x ac|^2. Where it is a rounding error, vb / denom and vc / denom are noise
  // and the point they give can lie anywhere in the triangle's plane: such a triangle has
  // no inside, and its closest point is its edges'.
  const double denom = va + vb + vc;
  if (!too_thin_for_a_plane(ab, ac, denom)) return a + ab * (vb / denom) + ac * (vc / denom);
  auto on_segment = [&p](const Vec3& from, const Vec3& to) {
    const Vec3 d = to - from;
    const double length2 = dot(d, d);
    const double s = length2 > 0 ? std::clamp(dot(p - from, d) / length2, 0.0, 1.0) : 0.0;
    return from + d * s;
  };
  Vec3 best = on_segment(a, b);
  for (const Vec3& q : {on_segment(b, c), on_segment(c, a)})
    if (squared_norm(q - p) < squared_norm(best - p)) best = q;
  return best;
}

void AxisBox::add(const Vec3& p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

double AxisBox::squared_distance(const Vec3& p) const {
  const double dx = std::max({lo.x - p.x, 0.0, p.x - hi.x});
  const double dy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
  const double dz = std::max({lo.z - p.z, 0.0, p.z - hi.z});
  return dx * dx + dy * dy + dz * dz;
}

TriangleTree::TriangleTree(std::span<const Vec3> positions, std::span<const Triangle> triangles)
    : order_(triangles.size()) {
  std::iota(order_.begin(), order_.end(), 0u);
  if (triangles.empty()) return;
  std::vector<Vec3> centroids(triangles.size());
  corners_.resize(3 * triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int i = 0; i < 3; ++i) corners_[3 * t + i] = positions[triangles[t][i]];
    centroids[t] = (corners_[3 * t] + corners_[3 * t + 1] + corners_[3 * t + 2]) * (1.0 / 3);
  }
  children_.reserve(triangles.size() / 2 + 1);
  root_ = build(0, triangles.size(), centroids, root_box_);
  // The corners in leaf order (they were in input order while building).
  std::vector<Vec3> by_leaf(corners_.size());
  for (size_t k = 0; k < order_.size(); ++k)
    for (int i = 0; i < 3; ++i) by_leaf[3 * k + i] = corners_[3 * size_t{order_[k]} + i];
  corners_ = std::move(by_leaf);
  for (int a = 0; a < 3; ++a)
    magnitude_ = std::max({magnitude_, std::abs(root_box_.lo[a]), std::abs(root_box_.hi[a])});
}

double TriangleTree::slack_at(const Vec3& p) const {
  return 1e-13 * std::max({magnitude_, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
}

TriangleTree::Closest TriangleTree::closest(const Vec3& p) const {
  return search(p, [](uint32_t) { return false; });
}

TriangleTree::Closest TriangleTree::closest(const Vec3& p, std::span<const char> left_out) const {
  return search(p, [left_out](uint32_t triangle) { return left_out[triangle] != 0; });
}

double TriangleTree::squared_distance_over(const Vec3& p, double floor) const {
  return search(
             p, [](uint32_t) { return false; }, floor)
      .squared_distance;
}

namespace {

// Two doubles in one register (GCC/Clang vector extensions: SSE2 on x86-64, NEON on
// arm64): the search measures two boxes, or two axes, at once. Each lane's arithmetic is
// the scalar code's (std::min / std::max: the first argument on ties), so the answers are
// the same bit for bit.
using Lanes = double __attribute__((vector_size(16)));
static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 is x, y, z in a row");
constexpr Lanes kZero = {0.0, 0.0};
inline Lanes lane_max(Lanes a, Lanes b) {
  return a < b ? b : a;
}
inline Lanes lane_min(Lanes a, Lanes b) {
  return b < a ? b : a;
}

}  // namespace

template <class Skip>
TriangleTree::Closest TriangleTree::search(const Vec3& p, Skip skip, double good_enough) const {
  Closest best;
  if (order_.empty()) return best;
  const double slack = slack_at(p);
  double skip_above = std::numeric_limits<double>::infinity();
  // A stack on the stack: this runs millions of times (distances, fits, remesh), and a
  // heap vector per query cost as much as the search on small trees. The median split
  // keeps the depth at most log2(triangles) + 1, and a search holds at most depth + 1
  // entries; each entry keeps its box's distance, computed once. The arithmetic is
  // AxisBox::squared_distance's, term for term, so the visiting order (and with it which
  // of equally near triangles answers) is that of a tree of AxisBox nodes.
  struct Entry {
    Node node;
    double box_distance;
  };
  Entry stack[kMaxDepth + 2];
  int size = 0;
  stack[size++] = {root_, root_box_.squared_distance(p)};
  const double q[3] = {p.x, p.y, p.z};
  const Lanes xy = {p.x, p.y};
  while (size > 0) {
    const Entry entry = stack[--size];
    if (entry.box_distance >= best.squared_distance) continue;
    const Node node = entry.node;
    if (node.count) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        if (skip(order_[k])) continue;
        const Vec3* c = &corners_[3 * size_t{k}];
        // The triangle's own box first: one farther than the best so far (with the slack)
        // holds no nearer point, and costs a fraction of closest_on_triangle.
        // x and y in the lanes of one vector, z alone; the sum in the scalar's order.
        Lanes corner[3];
        for (int i = 0; i < 3; ++i)
          std::memcpy(&corner[i], reinterpret_cast<const char*>(&c[i]), sizeof(Lanes));
        const Lanes low = lane_min(lane_min(corner[0], corner[1]), corner[2]);
        const Lanes high = lane_max(lane_max(corner[0], corner[1]), corner[2]);
        const Lanes gaps = lane_max(lane_max(low - xy, kZero), xy - high);
        const double gap_z = std::max(std::max(std::min({c[0].z, c[1].z, c[2].z}) - p.z, 0.0),
                                      p.z - std::max({c[0].z, c[1].z, c[2].z}));
        const double box_distance = (gaps[0] * gaps[0] + gaps[1] * gaps[1]) + gap_z * gap_z;
        if (box_distance > skip_above) continue;
        const Vec3 point = closest_on_triangle(p, c[0], c[1], c[2]);
        const double d2 = squared_norm(point - p);
        if (d2 < best.squared_distance) {
          best = {d2, point, order_[k]};
          if (d2 <= good_enough) return best;
          skip_above = (std::sqrt(d2) + slack) * (std::sqrt(d2) + slack);
        }
      }
      continue;
    }
    const Children& boxes = children_[node.first];
    // Both children at once, one lane each.
    Lanes sum;
    for (int axis = 0; axis < 3; ++axis) {
      Lanes lo, hi;
      std::memcpy(&lo, boxes.lo[axis], sizeof lo);
      std::memcpy(&hi, boxes.hi[axis], sizeof hi);
      const Lanes gap = lane_max(lane_max(lo - q[axis], kZero), q[axis] - hi);
      sum = axis == 0 ? gap * gap : sum + gap * gap;
    }
    const double d[2] = {sum[0], sum[1]};
    // Nearer child last, so it is searched first.
    const bool left_nearer = d[0] < d[1];
    const Entry l{boxes.node[0], d[0]}, r{boxes.node[1], d[1]};
    stack[size++] = left_nearer ? r : l;
    stack[size++] = left_nearer ? l : r;
  }
  return best;
}

// The node of triangles order_[begin, end), whose box goes to `box`; corners_ and
// centroids are still in input order.
TriangleTree::Node TriangleTree::build(size_t begin, size_t end, std::vector<Vec3>& centroids,
                                       AxisBox& box) {
  if (end - begin <= 4) {
    for (size_t k = begin; k < end; ++k)
      for (int i = 0; i < 3; ++i) box.add(corners_[3 * size_t{order_[k]} + i]);
    return {static_cast<uint32_t>(begin), static_cast<uint32_t>(end - begin)};
  }
  AxisBox centres;
  for (size_t k = begin; k < end; ++k) centres.add(centroids[order_[k]]);
  const Vec3 extent = centres.hi - centres.lo;
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const size_t mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  const uint32_t index = static_cast<uint32_t>(children_.size());
  children_.emplace_back();
  AxisBox boxes[2];
  const Node left = build(begin, mid, centroids, boxes[0]);
  const Node right = build(mid, end, centroids, boxes[1]);
  // The node's box from its children's (the same minima and maxima): reading every corner
  // again at every level was most of the build, 8% of a horse envelope's time.
  for (const AxisBox& child : boxes) box.add(child.lo), box.add(child.hi);
  Children& children = children_[index];
  children.node[0] = left, children.node[1] = right;
  for (int lane = 0; lane < 2; ++lane)
    for (int a = 0; a < 3; ++a) {
      children.lo[a][lane] = boxes[lane].lo[a];
      children.hi[a][lane] = boxes[lane].hi[a];
    }
  return {index, 0};
}

double farthest_from(const TriangleTree& tree, std::span<const Vec3> positions,
                     std::span<const Triangle> triangles) {
  constexpr int kSteps = 4;
  double farthest = 0;
  for (const Triangle& t : triangles) {
    const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; i + j <= kSteps; ++j) {
        const double u = double(i) / kSteps, v = double(j) / kSteps;
        farthest = std::max(farthest, tree.squared_distance(a + (b - a) * u + (c - a) * v));
      }
  }
  return std::sqrt(farthest);
}

TriangleTree polygon_tree(const PolygonMesh& mesh, std::span<const uint32_t> faces) {
  std::vector<Triangle> triangles;
  for (uint32_t f : faces) {
    const auto face = mesh.face(f);
    for (size_t k = 1; k + 1 < face.size(); ++k)
      triangles.push_back({face[0], face[k], face[k + 1]});
  }
  return TriangleTree(mesh.positions, triangles);
}

}  // namespace spheremap
