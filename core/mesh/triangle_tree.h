// Closest-point queries on a set of triangles: an AABB tree (median split on the longest
// axis of the centroids, leaves of at most 4 triangles).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

// The closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5);
// a degenerate triangle answers a.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct AxisBox {
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::lowest()};
  void add(const Vec3& p);
  double squared_distance(const Vec3& p) const;  // 0 inside
};

// positions and triangles must outlive the tree.
class TriangleTree {
 public:
  TriangleTree(std::span<const Vec3> positions, std::span<const Triangle> triangles);

  struct Closest {
    double squared_distance = std::numeric_limits<double>::max();  // max when empty
    Vec3 point;
    uint32_t triangle = 0;
  };
  Closest closest(const Vec3& p) const;
  double squared_distance(const Vec3& p) const { return closest(p).squared_distance; }

 private:
  struct Node {
    AxisBox box;
    uint32_t first = 0;  // leaf: first triangle in order_; inner: left child (right = +1)
    uint32_t count = 0;  // leaf: triangles; 0 for an inner node
  };
  void build(uint32_t index, size_t begin, size_t end);
  // Deeper than any median-split tree of up to 2^62 triangles (leaves of 1-4).
  static constexpr int kMaxDepth = 64;

  std::span<const Vec3> positions_;
  std::span<const Triangle> triangles_;
  std::vector<uint32_t> order_;
  std::vector<Vec3> centroids_;
  std::vector<Node> nodes_;
};

}  // namespace spheremap
