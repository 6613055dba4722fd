// Closest-point queries on a set of triangles: an AABB tree (median split on the longest
// axis of the centroids, leaves of at most 4 triangles). Laid out for the query: an inner
// node keeps both children's boxes side by side (one visit measures both), and the leaves'
// corners are copied in leaf order (no index chase per triangle).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

// The closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5);
// a triangle too thin for barycentric coordinates (its corners on, or within rounding of,
// one line) answers the closest point of its edges.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Whether |ab x ac|^2 is within rounding of 0 against |ab|^2 |ac|^2 (1e-10: the angle at a
// under 1e-5 radians or within it of 180 degrees): then neither the triangle's normal nor
// barycentric coordinates in it mean anything, and it is to be treated as its edges.
inline bool too_thin_for_a_plane(const Vec3& ab, const Vec3& ac, double cross_squared) {
  return !(cross_squared > 1e-10 * dot(ab, ab) * dot(ac, ac));
}

struct AxisBox {
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  Vec3 hi{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::lowest()};
  void add(const Vec3& p);
  double squared_distance(const Vec3& p) const;  // 0 inside
};

// The tree copies the corners it needs: positions and triangles may go after construction.
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
  // squared_distance(p) where it is over `floor`; else some triangle's squared distance at
  // most `floor` (the search stops at the first it finds). For a largest distance over
  // many points: a point already as near as the largest so far need not be measured.
  double squared_distance_over(const Vec3& p, double floor) const;
  // The closest point of the triangles whose `left_out` entry (one per triangle given to the
  // constructor) is 0: the least distance over them, as a tree of those alone answers it,
  // without building one.
  Closest closest(const Vec3& p, std::span<const char> left_out) const;

 private:
  // A leaf is triangles order_[first, first + count); an inner node (count 0) is
  // children_[first], which holds both children and their boxes (axis by axis, lane 0
  // the left child), so that a visit reads one record and pushes children without
  // reading them.
  struct Node {
    uint32_t first = 0;
    uint32_t count = 0;
  };
  struct Children {
    double lo[3][2], hi[3][2];
    Node node[2];
  };
  // How far (in distance) a computed closest point may stray outside its triangle's box
  // by rounding, with a wide margin, for a query at p.
  double slack_at(const Vec3& p) const;
  // The search of closest(), over the triangles for which skip(triangle) is false.
  // With `good_enough`: the first triangle at most that (squared) far answers.
  template <class Skip>
  Closest search(const Vec3& p, Skip skip, double good_enough = -1) const;
  Node build(size_t begin, size_t end, std::vector<Vec3>& centroids, AxisBox& box);
  // Deeper than any median-split tree of up to 2^62 triangles (leaves of 1-4).
  static constexpr int kMaxDepth = 64;

  std::vector<uint32_t> order_;  // the triangles in leaf order
  std::vector<Vec3> corners_;    // corners_[3k + i]: corner i of triangle order_[k]
  double magnitude_ = 0;         // the largest absolute corner coordinate
  AxisBox root_box_;
  Node root_;
  std::vector<Children> children_;
};

// How far `triangles` (over `positions`) stray from the tree's: the largest distance over
// points spread on each (a 4 x 4 barycentric grid, corners included: a flat cap's farthest
// point is inside it, not at its corners, which lie on the surface it closes).
double farthest_from(const TriangleTree& tree, std::span<const Vec3> positions,
                     std::span<const Triangle> triangles);

// A tree of the polygons `faces` of `mesh`, each fanned from its first corner (a flat
// polygon's points do not depend on its diagonals). O(corners log corners).
TriangleTree polygon_tree(const PolygonMesh& mesh, std::span<const uint32_t> faces);

}  // namespace spheremap
