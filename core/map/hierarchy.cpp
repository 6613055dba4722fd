#include "core/map/hierarchy.h"

#include "core/map/collapse_cost.h"
#include "core/map/incidence_lists.h"
#include "core/mesh/parallel.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

namespace spheremap {
namespace {

// Asks `should_stop` every kInterval vertices; throws HierarchyStopped when it says yes.
class HierarchyClock {
 public:
  explicit HierarchyClock(const std::function<bool()>& should_stop) : should_stop_(should_stop) {}
  void tick() {
    if (!should_stop_ || ++count_ % kInterval != 0) return;
    if (should_stop_()) throw HierarchyStopped();
  }

 private:
  static constexpr size_t kInterval = 4096;  // ~1-5 ms of collapses
  const std::function<bool()>& should_stop_;
  size_t count_ = 0;
};

// best = min(best, (cost, v)) in the order of pairs, written out: std::pair's comparison
// goes through a double's three-way comparison, the hierarchy's most frequent one.
inline void keep_cheaper(std::pair<double, uint32_t>& best, double cost, uint32_t v) {
  if (cost < best.first || (cost == best.first && v < best.second)) best = {cost, v};
}

// A triangle mesh that supports half-edge collapses: triangles with alive flags and
// per-vertex lists of incident alive triangles.
class CollapsibleMesh {
 public:
  CollapsibleMesh(std::span<const Vec3> positions, std::span<const Triangle> triangles)
      : x_(positions),
        tris_(triangles.begin(), triangles.end()),
        tri_alive_(triangles.size(), 1),
        incident_(positions.size(), triangles),
        alive_vertices_(positions.size()) {}

  size_t alive_vertices() const { return alive_vertices_; }
  bool alive(uint32_t v) const { return !incident_.empty(v); }

  // Whether u or any vertex of its ring is flagged (no ring ordering needed).
  bool star_touched(uint32_t u, const std::vector<char>& flags) const {
    for (uint32_t t : incident_[u])
      for (uint32_t w : tris_[t])
        if (flags[w]) return true;
    return false;
  }

  // The ring of u as an oriented cycle: star triangles are (u, r_i, r_i+1).
  void ordered_ring(uint32_t u, std::vector<uint32_t>& ring) const {
    ring.clear();
    pairs_.clear();
    for (uint32_t t : incident_[u]) {
      const Triangle& tri = tris_[t];
      const int k = tri[0] == u ? 0 : (tri[1] == u ? 1 : 2);
      pairs_.push_back({tri[(k + 1) % 3], tri[(k + 2) % 3]});
    }
    uint32_t current = pairs_[0][0];
    for (size_t step = 0; step < pairs_.size(); ++step) {
      ring.push_back(current);
      auto next = std::find_if(pairs_.begin(), pairs_.end(),
                               [&](const std::array<uint32_t, 2>& p) { return p[0] == current; });
      if (next == pairs_.end()) throw std::runtime_error("hierarchy: vertex ring is not a cycle");
      current = (*next)[1];
    }
  }

  // Each vertex of u's ring once: the corner after u in each of u's triangles.
  template <class Visit>
  void for_each_neighbor(uint32_t u, Visit&& visit) const {
    for (uint32_t t : incident_[u]) {
      const Triangle& tri = tris_[t];
      visit(tri[tri[0] == u ? 1 : (tri[1] == u ? 2 : 0)]);
    }
  }

  // The cost of u's cheapest collapse onto a neighbour, and that neighbour (the lowest id
  // among equal costs: the first candidate collapse_round would try).
  std::pair<double, uint32_t> cheapest_collapse(uint32_t u, const CollapseCost& cost) const {
    std::pair<double, uint32_t> best{INFINITY, u};
    for_each_neighbor(u, [&](uint32_t w) { keep_cheaper(best, cost(u, w), w); });
    return best;
  }

  // Link condition: ring(u) and ring(v) share exactly the two vertices opposite u->v.
  // `in_ring_u` flags ring(u)'s vertices: one pass over v's ring instead of a search of v's
  // triangles per vertex of ring(u) (neither ring holds u or v twice: the mesh stays a
  // closed manifold, and u is not in ring(u) nor v in ring(v)).
  bool link_condition(uint32_t v, const std::vector<char>& in_ring_u) const {
    size_t shared = 0;
    for_each_neighbor(v, [&](uint32_t w) { shared += in_ring_u[w]; });
    return shared == 2;
  }

  // Moving u onto v must not degenerate or turn any remaining triangle's normal by more
  // than ~78 degrees (n0 . n1 > 0.2 |n0| |n1|).
  bool keeps_geometry(uint32_t u, uint32_t v) const {
    for (uint32_t t : incident_[u]) {
      const Triangle& tri = tris_[t];
      if (tri[0] == v || tri[1] == v || tri[2] == v) continue;
      const int k = tri[0] == u ? 0 : (tri[1] == u ? 1 : 2);
      const Vec3& p = x_[tri[(k + 1) % 3]];
      const Vec3& q = x_[tri[(k + 2) % 3]];
      const Vec3 n0 = cross(p - x_[u], q - x_[u]), n1 = cross(p - x_[v], q - x_[v]);
      if (!(dot(n0, n1) > 0.2 * norm(n0) * norm(n1))) return false;
    }
    return true;
  }

  void collapse(uint32_t u, uint32_t v) {
    for (size_t k = 0; k < incident_.size(u); ++k) {  // by index: append may move lists
      const uint32_t t = incident_.at(u, k);
      Triangle& tri = tris_[t];
      if (tri[0] == v || tri[1] == v || tri[2] == v) {
        tri_alive_[t] = 0;
        for (uint32_t w : tri)
          if (w != u) incident_.erase(w, t);
      } else {
        for (uint32_t& w : tri)
          if (w == u) w = v;
        incident_.append(v, t);
      }
    }
    incident_.clear(u);
    --alive_vertices_;
  }

  // The alive triangles in id order. The alive flags are read eight at a time and a word
  // of dead ones is skipped: at the coarse levels most are dead, and a list of the alive
  // ids instead would cost 4 bytes per triangle where the 17M-triangle map peaks (measured:
  // +0.06 GiB). Of horse's 345M instructions the snapshots took 9M reading flag by flag.
  std::vector<Triangle> alive_triangles() const {
    std::vector<Triangle> out;
    const size_t count = tris_.size();
    size_t t = 0;
    for (; t + 8 <= count; t += 8) {
      uint64_t word;
      std::memcpy(&word, tri_alive_.data() + t, sizeof word);
      if (word == 0) continue;
      for (size_t k = t; k < t + 8; ++k)
        if (tri_alive_[k]) out.push_back(tris_[k]);
    }
    for (; t < count; ++t)
      if (tri_alive_[t]) out.push_back(tris_[t]);
    return out;
  }

 private:
  std::span<const Vec3> x_;
  std::vector<Triangle> tris_;
  std::vector<char> tri_alive_;
  IncidenceLists incident_;
  size_t alive_vertices_;
  mutable std::vector<std::array<uint32_t, 2>> pairs_;
};

// The collapses in order, their rings (input ids, oriented) in one flat array.
struct CollapseLog {
  struct Entry {
    uint32_t u, v;
    uint32_t ring_begin, ring_end;  // into rings
  };
  std::vector<Entry> entries;
  std::vector<uint32_t> rings;

  void add(uint32_t u, uint32_t v, const std::vector<uint32_t>& ring) {
    const auto begin = static_cast<uint32_t>(rings.size());
    rings.insert(rings.end(), ring.begin(), ring.end());
    entries.push_back({u, v, begin, static_cast<uint32_t>(rings.size())});
  }
  std::span<const uint32_t> ring(const Entry& e) const {
    return {rings.data() + e.ring_begin, e.ring_end - e.ring_begin};
  }
};

// A vertex's place in the order: (cheapest collapse cost, id) as two integers. A cost is
// never negative nor NaN (a clamped mean squared distance plus a squared length), and the
// bits of such doubles order as the doubles do, so comparing the bits orders the entries
// as comparing the pair of double and id did, without a floating-point comparison's
// partial ordering (those comparisons were 7% of the hierarchy's instructions, horse).
struct OrderEntry {
  uint64_t cost_bits;
  uint32_t vertex;

  OrderEntry() = default;
  OrderEntry(double cost, uint32_t v) : cost_bits(std::bit_cast<uint64_t>(cost)), vertex(v) {}
  friend bool operator<(const OrderEntry& a, const OrderEntry& b) {
    return a.cost_bits < b.cost_bits || (a.cost_bits == b.cost_bits && a.vertex < b.vertex);
  }
};

// Alive vertices by (cheapest collapse cost, id), kept sorted across rounds: a round
// changes the keys of the vertices around its collapses only, so it re-sorts those and
// merges them back instead of sorting every alive vertex again (that sort and a scan of
// all n vertices per round were a fifth of the hierarchy's time at 100K faces).
using Order = std::vector<OrderEntry>;

// Per vertex: its key (the cost of its cheapest collapse) and the neighbour it collapses
// onto at that cost. A collapse u -> v changes only the quadric of v and the neighbours of
// the vertices around it, so a neighbour w of v whose cheapest collapse went neither to u
// nor to a vertex whose quadric grew keeps every cost it had, and gains or changes only
// those onto such vertices: its new key is the old one or one of those, found with one or
// two cost evaluations instead of one per neighbour (the same minimum over the same
// numbers, so the same hierarchy; re-keying was most of a round's time).
struct Keys {
  std::vector<double> key;
  std::vector<uint32_t> onto;
  std::vector<char> grew;  // the quadric grew this round (a collapse target)
};

// One round: an independent set of collapses (touched = u and its ring), vertices taken
// in order of their cheapest collapse (the key in `order`), each trying its ring cheapest
// first. A collapse u -> v changes the keys of v and
// its neighbours only (v's quadric grew, the ring's edges changed), so the round
// refreshes those at its end, and `order` with them.
size_t collapse_round(CollapsibleMesh& mesh, CollapseCost& cost, bool geometric_test,
                      CollapseLog& log, std::vector<char>& touched, std::vector<char>& stale,
                      std::vector<char>& in_ring, Order& order, Keys& keys, HierarchyClock& clock,
                      int threads) {
  std::vector<uint32_t> ring;
  std::vector<uint32_t> stale_list, grown;
  std::vector<std::pair<double, uint32_t>> candidates;
  auto mark_stale = [&](uint32_t w) {
    if (!stale[w]) stale[w] = 1, stale_list.push_back(w);
  };
  size_t collapsed = 0;
  auto collapse = [&](uint32_t u, uint32_t v) {
    log.add(u, v, ring);
    mesh.collapse(u, v);
    cost.merge(u, v);
    keys.grew[v] = 1, grown.push_back(v);
    touched[u] = 1;
    mark_stale(u);
    for (uint32_t w : ring) touched[w] = 1;
    mark_stale(v);
    mesh.for_each_neighbor(v, mark_stale);
    ++collapsed;
  };
  auto allowed = [&](uint32_t u, uint32_t v) {
    return mesh.link_condition(v, in_ring) && (!geometric_test || mesh.keeps_geometry(u, v));
  };
  for (const OrderEntry& entry : order) {
    const uint32_t u = entry.vertex;
    if (mesh.alive_vertices() <= 4) break;
    clock.tick();
    if (mesh.star_touched(u, touched)) continue;
    mesh.ordered_ring(u, ring);
    for (uint32_t w : ring) in_ring[w] = 1;
    // The cheapest candidate is known without a cost: u's star is untouched since its key
    // was computed (a collapse touches its ring, and every neighbour of its target is in
    // it), so keys.onto[u] is still the lowest (cost, id), the first of the sorted
    // candidates below. It is nearly always allowed; the candidates' costs are needed only
    // when it is not (horse: 721 of 48,481 collapses), and they then give the same order.
    if (allowed(u, keys.onto[u])) {
      collapse(u, keys.onto[u]);
    } else {
      candidates.clear();
      for (uint32_t w : ring) candidates.push_back({cost(u, w), w});
      std::sort(candidates.begin(), candidates.end());
      for (const auto& [price, v] : candidates)
        if (v != keys.onto[u] && allowed(u, v)) {
          collapse(u, v);
          break;
        }
    }
    for (uint32_t w : ring) in_ring[w] = 0;
  }
  // New keys for the stale vertices still alive (every touched vertex is stale: u, and
  // its ring, now v's neighbours), in parallel: reading the mesh and quadrics is most of
  // a round's time. `threads` threads, as asked: without num_threads a --threads 1 run had a
  // second thread, spinning between rounds (13% of its CPU samples, horse, fast).
  std::vector<std::pair<double, uint32_t>> merged;
  for (uint32_t w : stale_list)
    if (mesh.alive(w)) merged.push_back({keys.key[w], w});
  const long long count = static_cast<long long>(merged.size());
#pragma omp parallel for schedule(static) num_threads(threads) if (count > 4096)
  for (long long k = 0; k < count; ++k) {
    auto& entry = merged[static_cast<size_t>(k)];  // each writes its own
    const uint32_t w = entry.second;  // a plain name: clang 14 cannot capture a binding
    const uint32_t onto = keys.onto[w];
    std::pair<double, uint32_t> best;
    if (keys.grew[w] || !mesh.alive(onto) || keys.grew[onto]) {
      best = mesh.cheapest_collapse(w, cost);
    } else {
      best = {keys.key[w], onto};
      mesh.for_each_neighbor(w, [&](uint32_t t) {
        if (keys.grew[t]) keep_cheaper(best, cost(w, t), t);
      });
    }
    entry.first = best.first;
    keys.onto[w] = best.second;
  }
  for (uint32_t v : grown) keys.grew[v] = 0;
  // A vertex whose key did not change keeps its place in the order; the removed ones and
  // those with new keys leave it and come back sorted (fewer to sort: sorting them was a
  // quarter of the hierarchy's instructions).
  std::erase_if(merged, [&](const std::pair<double, uint32_t>& entry) {
    const bool same = entry.first == keys.key[entry.second];
    if (same) stale[entry.second] = 0;
    keys.key[entry.second] = entry.first;
    return same;
  });
  std::erase_if(order, [&](const OrderEntry& entry) { return stale[entry.vertex] != 0; });
  for (uint32_t w : stale_list) stale[w] = touched[w] = 0;
  const size_t kept = order.size();
  for (const auto& [key, w] : merged) order.emplace_back(key, w);
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(kept), order.end());
  std::inplace_merge(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(kept), order.end());
  return collapsed;
}

std::vector<Triangle> renumbered(std::vector<Triangle> triangles,
                                 const std::vector<uint32_t>& old_to_new) {
  for (Triangle& t : triangles)
    for (uint32_t& v : t) v = old_to_new[v];
  return triangles;
}

// What the collapses leave: their log, the level snapshots (input ids, finest first) and
// sizes, the vertices never collapsed, and the round counts.
struct Collapsed {
  CollapseLog log;
  std::vector<std::vector<Triangle>> snapshots;
  std::vector<uint32_t> sizes;
  std::vector<uint32_t> survivors;  // ascending input ids: the tetrahedron
  size_t rounds = 0, round_geometry_dropped = 0;
};

// Collapses down to the tetrahedron. Its working data (the collapsible mesh, quadrics,
// order and keys: most of the hierarchy's memory) is gone when it returns, before the
// hierarchy is assembled beside the log (at 17M triangles the two together were the peak
// of the whole map).
Collapsed collapse_all(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                       double level_growth, HierarchyClock& clock, int threads) {
  const size_t n = positions.size();
  CollapsibleMesh mesh(positions, triangles);
  Collapsed out;
  out.sizes.push_back(static_cast<uint32_t>(n));
  bool geometric_test = true;
  std::vector<char> touched(n, 0), stale(n, 0), in_ring(n, 0);
  CollapseCost cost(positions, triangles);
  Order order(n);
  Keys keys{std::vector<double>(n), std::vector<uint32_t>(n), std::vector<char>(n, 0)};
  for (uint32_t u = 0; u < n; ++u) {
    clock.tick();
    const auto [key, onto] = mesh.cheapest_collapse(u, cost);
    order[u] = OrderEntry(key, u);
    keys.key[u] = key, keys.onto[u] = onto;
  }
  std::sort(order.begin(), order.end());
  while (mesh.alive_vertices() > 4) {
    const size_t collapsed = collapse_round(mesh, cost, geometric_test, out.log, touched, stale,
                                            in_ring, order, keys, clock, threads);
    if (collapsed == 0) {
      if (!geometric_test) throw std::runtime_error("hierarchy: no collapsible edge left");
      geometric_test = false;
      out.round_geometry_dropped = out.rounds + 1;
      continue;
    }
    ++out.rounds;
    const size_t alive = mesh.alive_vertices();
    if (alive == 4 || static_cast<double>(alive) * level_growth <= out.sizes.back()) {
      out.sizes.push_back(static_cast<uint32_t>(alive));
      out.snapshots.push_back(mesh.alive_triangles());
    }
  }
  if (out.snapshots.empty()) out.snapshots.push_back(mesh.alive_triangles());  // a tetrahedron
  if (out.sizes.back() != 4) out.sizes.push_back(4);
  for (uint32_t v = 0; v < n; ++v)
    if (mesh.alive(v)) out.survivors.push_back(v);
  return out;
}

}  // namespace

CollapseHierarchy build_hierarchy(std::span<const Vec3> positions,
                                  std::span<const Triangle> triangles, double level_growth,
                                  const std::function<bool()>& should_stop, int threads) {
  HierarchyClock clock(should_stop);
  const size_t n = positions.size();
  Collapsed c = collapse_all(positions, triangles, level_growth, clock, resolve_threads(threads));
  CollapseHierarchy h;
  h.rounds = c.rounds;
  h.round_geometry_dropped = c.round_geometry_dropped;

  // New ids: the tetrahedron (ascending input id), then reverse removal order.
  h.old_to_new.assign(n, 0);
  h.new_to_old = std::move(c.survivors);
  for (auto it = c.log.entries.rbegin(); it != c.log.entries.rend(); ++it)
    h.new_to_old.push_back(it->u);
  for (uint32_t id = 0; id < n; ++id) h.old_to_new[h.new_to_old[id]] = id;

  h.level_sizes.assign(c.sizes.rbegin(), c.sizes.rend());
  for (auto it = c.snapshots.rbegin(); it != c.snapshots.rend(); ++it)
    h.level_triangles.push_back(renumbered(std::move(*it), h.old_to_new));

  h.collapse_target.assign(n, 0);
  h.ring_offsets.assign(n + 1, 0);
  for (uint32_t id = 4; id < n; ++id) {
    const CollapseLog::Entry& e = c.log.entries[n - 1 - id];
    h.collapse_target[id] = h.old_to_new[e.v];
    h.ring_offsets[id + 1] = e.ring_end - e.ring_begin;
  }
  for (size_t id = 0; id < n; ++id) h.ring_offsets[id + 1] += h.ring_offsets[id];
  h.rings.resize(h.ring_offsets.back());
  for (uint32_t id = 4; id < n; ++id) {
    const std::span<const uint32_t> ring = c.log.ring(c.log.entries[n - 1 - id]);
    for (size_t k = 0; k < ring.size(); ++k)
      h.rings[h.ring_offsets[id] + k] = h.old_to_new[ring[k]];
  }
  return h;
}

}  // namespace spheremap
