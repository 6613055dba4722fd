#include "core/mesh/triangle_tree.h"

#include <algorithm>
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
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate triangle
  return a + ab * (vb / denom) + ac * (vc / denom);
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
    : positions_(positions), triangles_(triangles), order_(triangles.size()) {
  std::iota(order_.begin(), order_.end(), 0u);
  centroids_.resize(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    centroids_[t] =
        (positions[triangles[t][0]] + positions[triangles[t][1]] + positions[triangles[t][2]]) *
        (1.0 / 3);
  if (triangles.empty()) return;
  nodes_.reserve(2 * triangles.size() / 4 + 2);
  nodes_.emplace_back();
  build(0, 0, triangles.size());
}

TriangleTree::Closest TriangleTree::closest(const Vec3& p) const {
  Closest best;
  if (nodes_.empty()) return best;
  // A stack on the stack: this runs millions of times (distances, fits, remesh), and a
  // heap vector per query cost as much as the search on small trees. The median split
  // keeps the depth at most log2(triangles) + 1, and a search holds at most depth + 1
  // entries; each entry keeps its box's distance, computed once.
  struct Entry {
    uint32_t node;
    double box_distance;
  };
  Entry stack[kMaxDepth + 2];
  int size = 0;
  stack[size++] = {0, nodes_[0].box.squared_distance(p)};
  while (size > 0) {
    const Entry entry = stack[--size];
    if (entry.box_distance >= best.squared_distance) continue;
    const Node& node = nodes_[entry.node];
    if (node.count) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        const Triangle& t = triangles_[order_[k]];
        const Vec3 q = closest_on_triangle(p, positions_[t[0]], positions_[t[1]], positions_[t[2]]);
        const double d2 = squared_norm(q - p);
        if (d2 < best.squared_distance) best = {d2, q, order_[k]};
      }
      continue;
    }
    // Nearer child last, so it is searched first.
    const uint32_t l = node.first, r = node.first + 1;
    const double dl = nodes_[l].box.squared_distance(p), dr = nodes_[r].box.squared_distance(p);
    const bool left_nearer = dl < dr;
    stack[size++] = left_nearer ? Entry{r, dr} : Entry{l, dl};
    stack[size++] = left_nearer ? Entry{l, dl} : Entry{r, dr};
  }
  return best;
}

// Fills node `index` (already allocated) with triangles order_[begin, end).
void TriangleTree::build(uint32_t index, size_t begin, size_t end) {
  AxisBox box, centres;
  for (size_t k = begin; k < end; ++k) {
    for (uint32_t v : triangles_[order_[k]]) box.add(positions_[v]);
    centres.add(centroids_[order_[k]]);
  }
  nodes_[index].box = box;
  if (end - begin <= 4) {
    nodes_[index].first = static_cast<uint32_t>(begin);
    nodes_[index].count = static_cast<uint32_t>(end - begin);
    return;
  }
  const Vec3 extent = centres.hi - centres.lo;
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const size_t mid = (begin + end) / 2;
  std::nth_element(
      order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
      [&](uint32_t a, uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
  const uint32_t left = static_cast<uint32_t>(nodes_.size());  // the right child is left + 1
  nodes_.resize(nodes_.size() + 2);
  nodes_[index].first = left;
  build(left, begin, mid);
  build(left + 1, mid, end);
}

}  // namespace spheremap
