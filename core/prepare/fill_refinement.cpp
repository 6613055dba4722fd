#include "core/prepare/fill_refinement.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/prepare/hole_filling.h"

namespace spheremap {
namespace {

// Split passes (each splits every triangle still too large, so sizes halve about every
// pass: 64 is far beyond any budget) and Delaunay rounds after each.
constexpr size_t kMaxPasses = 64;
constexpr size_t kMaxRelaxRounds = 32;

Vec3 normal(const std::vector<Vec3>& p, const Triangle& t) {
  return cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

double angle_at(const Vec3& apex, const Vec3& p, const Vec3& q) {
  const Vec3 u = p - apex, v = q - apex;
  return std::atan2(norm(cross(u, v)), dot(u, v));
}

uint32_t third(const Triangle& t, uint32_t a, uint32_t b) {
  for (uint32_t v : t)
    if (v != a && v != b) return v;
  return t[0];
}

// The fill's triangles with the triangle of each directed edge.
class Fill {
 public:
  Fill(std::vector<Triangle>& triangles, const std::unordered_set<uint64_t>& edges,
       const std::vector<Vec3>& positions)
      : t_(triangles), edges_(edges), p_(positions) {
    for (uint32_t k = 0; k < t_.size(); ++k) link(k);
  }

  // Replaces triangle k by three around the new vertex v.
  void split(uint32_t k, uint32_t v) {
    const Triangle old = t_[k];
    unlink(k);
    t_[k] = {old[0], old[1], v};
    link(k);
    for (int i = 1; i < 3; ++i) {
      t_.push_back({old[i], old[(i + 1) % 3], v});
      link(static_cast<uint32_t>(t_.size() - 1));
    }
    for (int i = 0; i < 3; ++i) relax(old[i], old[(i + 1) % 3]);
  }

  // Swaps the edge a-b for the other diagonal of its two triangles when the angles facing it
  // sum to more than pi (not Delaunay), the other diagonal is not an edge yet and the two
  // new triangles face the way the old did. Returns whether it swapped.
  bool relax(uint32_t a, uint32_t b) {
    const auto i = at_.find(directed_edge_key(a, b)), j = at_.find(directed_edge_key(b, a));
    if (i == at_.end() || j == at_.end()) return false;  // a boundary edge
    const uint32_t k1 = i->second, k2 = j->second;
    const uint32_t c = third(t_[k1], a, b), d = third(t_[k2], a, b);
    if (c == d || at_.count(directed_edge_key(c, d)) || at_.count(directed_edge_key(d, c)) ||
        edges_.count(undirected_edge_key(c, d)))
      return false;
    if (!(angle_at(p_[c], p_[a], p_[b]) + angle_at(p_[d], p_[a], p_[b]) > std::numbers::pi + 1e-9))
      return false;
    // t1 runs a -> b -> c, t2 b -> a -> d; the quad b -> c -> a -> d.
    const Triangle n1 = {c, a, d}, n2 = {d, b, c};
    const Vec3 was = normal(p_, t_[k1]) + normal(p_, t_[k2]);
    const Vec3 m1 = normal(p_, n1), m2 = normal(p_, n2);
    if (!(dot(m1, m2) > 0 && dot(m1, was) > 0 && dot(m2, was) > 0)) return false;
    unlink(k1), unlink(k2);
    t_[k1] = n1, t_[k2] = n2;
    link(k1), link(k2);
    ++swaps;
    return true;
  }

  // Swaps until every edge is Delaunay (at most kMaxRelaxRounds rounds).
  void relax_all() {
    for (size_t round = 0; round < kMaxRelaxRounds; ++round) {
      bool any = false;
      for (uint32_t k = 0; k < t_.size(); ++k)
        for (int e = 0; e < 3; ++e) any = relax(t_[k][e], t_[k][(e + 1) % 3]) || any;
      if (!any) return;
    }
  }

  size_t swaps = 0;

 private:
  void link(uint32_t k) {
    for (int e = 0; e < 3; ++e) at_[directed_edge_key(t_[k][e], t_[k][(e + 1) % 3])] = k;
  }
  void unlink(uint32_t k) {
    for (int e = 0; e < 3; ++e) at_.erase(directed_edge_key(t_[k][e], t_[k][(e + 1) % 3]));
  }

  std::vector<Triangle>& t_;
  const std::unordered_set<uint64_t>& edges_;
  const std::vector<Vec3>& p_;
  std::unordered_map<uint64_t, uint32_t> at_;
};

// Moves the vertices from `base` on to the scale-dependent bi-Laplacian (thin-plate) surface over
// the fill and the loop corners' mesh rings, the rest fixed; returns false (positions as
// they were) when the system cannot be solved or the result would fold.
bool fair(PolygonMesh& mesh, uint32_t base, const std::vector<Triangle>& fill,
          const std::unordered_map<uint32_t, std::vector<uint32_t>>& ring, const StopCheck* stop) {
  const uint32_t m = static_cast<uint32_t>(mesh.vertex_count()) - base;
  std::unordered_map<uint32_t, uint32_t> local;  // fixed vertex -> local id (m ...)
  std::vector<uint32_t> global;                  // local id -> vertex
  for (uint32_t v = base; v < base + m; ++v) global.push_back(v);
  auto id = [&](uint32_t v) {
    if (v >= base) return v - base;
    const auto [it, added] = local.emplace(v, static_cast<uint32_t>(global.size()));
    if (added) global.push_back(v);
    return it->second;
  };
  // Neighbours of every vertex with a row (the new ones and the loop's corners).
  std::unordered_map<uint32_t, std::vector<uint32_t>> around;
  for (const Triangle& t : fill)
    for (int e = 0; e < 3; ++e) {
      around[id(t[e])].push_back(id(t[(e + 1) % 3]));
      around[id(t[(e + 1) % 3])].push_back(id(t[e]));
    }
  for (const auto& [v, neighbours] : ring) {
    if (!local.count(v)) continue;  // not a corner of this fill
    auto& list = around[local.at(v)];
    for (uint32_t w : neighbours) list.push_back(id(w));
  }
  if (stop) stop->check();
  const size_t n = global.size();
  std::vector<Eigen::Triplet<double>> entries;
  for (auto& [row, list] : around) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    // Liepa's scale-dependent umbrella: each neighbour weighs the inverse of its distance
    // (uniform weights let a fill denser than its ring sag: a sphere's cap faired 0.1 low).
    entries.emplace_back(row, row, -1.0);
    const Vec3& p = mesh.positions[global[row]];
    double total = 0;
    for (uint32_t w : list) total += 1 / std::max(norm(mesh.positions[global[w]] - p), 1e-300);
    for (uint32_t w : list)
      entries.emplace_back(row, w,
                           1 / std::max(norm(mesh.positions[global[w]] - p), 1e-300) / total);
  }
  Eigen::SparseMatrix<double> laplacian(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  laplacian.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> squared = laplacian * laplacian;
  const Eigen::SparseMatrix<double> a = squared.topLeftCorner(m, m);
  const Eigen::SparseMatrix<double> r = squared.topRightCorner(m, static_cast<Eigen::Index>(n) - m);
  Eigen::MatrixXd fixed(static_cast<Eigen::Index>(n) - m, 3);
  for (size_t k = m; k < n; ++k) {
    const Vec3& p = mesh.positions[global[k]];
    fixed(static_cast<Eigen::Index>(k - m), 0) = p.x;
    fixed(static_cast<Eigen::Index>(k - m), 1) = p.y;
    fixed(static_cast<Eigen::Index>(k - m), 2) = p.z;
  }
  const Eigen::MatrixXd rhs = -(r * fixed);
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(a);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  if (stop) stop->check();
  const std::vector<Vec3> before(mesh.positions.begin() + base, mesh.positions.end());
  for (uint32_t k = 0; k < m; ++k) mesh.positions[base + k] = {x(k, 0), x(k, 1), x(k, 2)};
  // No fold: every triangle keeps an area, and triangles sharing an edge turn by less than
  // a right angle about it.
  double scale = 0;
  for (const Triangle& t : fill) scale = std::max(scale, norm(normal(mesh.positions, t)));
  std::unordered_map<uint64_t, Vec3> facing;
  bool folds = false;
  for (const Triangle& t : fill) {
    const Vec3 nt = normal(mesh.positions, t);
    const double length = norm(nt);
    if (!(length > 1e-12 * scale)) folds = true;
    for (int e = 0; e < 3 && !folds; ++e) {
      const auto it = facing.find(directed_edge_key(t[(e + 1) % 3], t[e]));
      if (it != facing.end() && !(dot(it->second, nt * (1 / length)) > 0)) folds = true;
      facing[directed_edge_key(t[e], t[(e + 1) % 3])] = nt * (1 / length);
    }
    if (folds) break;
  }
  if (folds) std::copy(before.begin(), before.end(), mesh.positions.begin() + base);
  return !folds;
}

}  // namespace

size_t fill_vertex_budget(const PolygonMesh& mesh, std::span<const uint32_t> loop) {
  if (loop.size() < 3) return 0;
  double perimeter = 0;
  for (size_t k = 0; k < loop.size(); ++k)
    perimeter += norm(mesh.positions[loop[(k + 1) % loop.size()]] - mesh.positions[loop[k]]);
  const double mean = perimeter / static_cast<double>(loop.size());
  if (!(mean > 0)) return 0;
  const double edges = perimeter / mean;
  return static_cast<size_t>(std::min(static_cast<double>(kMaxFillVertices), edges * edges / 4));
}

FillRefinement refine_and_fair_fill(PolygonMesh& mesh, std::span<const uint32_t> loop,
                                    std::vector<Triangle>& fill,
                                    const std::unordered_set<uint64_t>& edges,
                                    const std::unordered_map<uint32_t, std::vector<uint32_t>>& ring,
                                    size_t max_vertices, const StopCheck* stop) {
  FillRefinement result;
  const size_t n = loop.size();
  if (n < 3 || fill.empty() || max_vertices == 0) return result;
  const uint32_t base = static_cast<uint32_t>(mesh.vertex_count());
  // sigma: the edge length wanted at a vertex; at a corner the mean of its two loop edges.
  std::unordered_map<uint32_t, double> corner_sigma;
  for (size_t k = 0; k < n; ++k) {
    const Vec3& p = mesh.positions[loop[k]];
    corner_sigma[loop[k]] = 0.5 * (norm(mesh.positions[loop[(k + 1) % n]] - p) +
                                   norm(mesh.positions[loop[(k + n - 1) % n]] - p));
  }
  std::vector<double> new_sigma;
  auto sigma = [&](uint32_t v) { return v >= base ? new_sigma[v - base] : corner_sigma.at(v); };
  Fill refined(fill, edges, mesh.positions);
  refined.relax_all();
  for (size_t pass = 0; pass < kMaxPasses && result.vertices_added < max_vertices; ++pass) {
    if (stop) stop->check();
    bool split = false;
    const size_t count = fill.size();
    for (uint32_t k = 0; k < count && result.vertices_added < max_vertices; ++k) {
      const Triangle t = fill[k];
      const Vec3 centroid =
          (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) * (1.0 / 3);
      const double s = (sigma(t[0]) + sigma(t[1]) + sigma(t[2])) / 3;
      const bool large = std::all_of(t.begin(), t.end(), [&](uint32_t v) {
        const double d = kFillDensity * norm(centroid - mesh.positions[v]);
        return d > s && d > sigma(v);
      });
      if (!large) continue;
      mesh.positions.push_back(centroid);
      new_sigma.push_back(s);
      refined.split(k, static_cast<uint32_t>(mesh.vertex_count() - 1));
      ++result.vertices_added;
      split = true;
    }
    if (!split) break;
    refined.relax_all();
  }
  result.swaps = refined.swaps;
  if (result.vertices_added > 0) result.faired = fair(mesh, base, fill, ring, stop);
  return result;
}

}  // namespace spheremap
