// The default method. First the stretch-optimized hierarchy (ALGORITHM §F): from a
// tetrahedron, every level inserted kernel-safe and then stretch-optimized. When a level
// cannot be made fold-free, the engine v1 map (ALGORITHM §B4, with the departures measured
// in BENCHMARKS.md): the paper's map of the whole mesh with a small budget; failing that,
// the hierarchy started from the paper's map of a coarse level (or a tetrahedron), then
// per level kernel-safe insertion, Lai-Cheng smoothing, local repair and a fold-free
// fallback, retried with other smoothing settings while the map folds. polish_map
// opens whatever a reader could not tell from a fold (each optimized map is judged
// polished).
#include <algorithm>
#include <numeric>
#include <optional>

#include "core/map/float32_rescue.h"
#include "core/map/hierarchy.h"
#include "core/map/insertion.h"
#include "core/map/limit_operator.h"
#include "core/map/map_check.h"
#include "core/map/map_session.h"
#include "core/map/partial_level.h"
#include "core/map/projected_map.h"
#include "core/map/repair.h"
#include "core/map/stretch_optimizer.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// The regular spherical tetrahedron on new ids 0..3, oriented like its triangles.
void place_tetrahedron(std::span<Vec3> q, std::span<const Triangle> tetrahedron) {
  const double s = 1.0 / std::sqrt(3.0);
  q[0] = {s, s, s}, q[1] = {s, -s, -s}, q[2] = {-s, s, -s}, q[3] = {-s, -s, s};
  const Triangle& t = tetrahedron[0];
  if (!is_valid_triangle(q[t[0]], q[t[1]], q[t[2]])) std::swap(q[0], q[1]);
}

SparseMatrix level_operator(std::span<const Triangle> triangles, size_t n, double alpha) {
  std::vector<uint32_t> offsets(triangles.size() + 1);
  for (size_t t = 0; t <= triangles.size(); ++t) offsets[t] = static_cast<uint32_t>(3 * t);
  return limit_operator(offsets, {triangles.data()->data(), 3 * triangles.size()}, n, alpha);
}

// The input polygons in hierarchy ids, for the finest level's operator.
SparseMatrix fine_operator(const PolygonMesh& mesh, const std::vector<uint32_t>& old_to_new,
                           double alpha) {
  std::vector<uint32_t> indices(mesh.indices.size());
  for (size_t k = 0; k < indices.size(); ++k) indices[k] = old_to_new[mesh.indices[k]];
  return limit_operator(mesh.offsets, indices, mesh.vertex_count(), alpha);
}

class CoarseToFine {
 public:
  CoarseToFine(const PolygonMesh& mesh, std::span<const Triangle> triangles,
               const MapSession& session, MapResult& result, double level_growth)
      : mesh_(mesh), session_(session), options_(session.options()), result_(result) {
    session_.report({.stage = "hierarchy"});
    const double start = session_.elapsed();
    h_ = build_hierarchy(
        mesh.positions, triangles, level_growth, [&] { return session_.should_stop(); },
        options_.smoothing.threads);
    result_.hierarchy_seconds = session_.elapsed() - start;
    result_.hierarchy_rounds = h_.rounds;
    fine_triangles_.assign(triangles.begin(), triangles.end());
    const std::span<const double> weights = session.triangle_weights();
    if (weights.size() == triangles.size()) fine_weights_.assign(weights.begin(), weights.end());
    for (Triangle& t : fine_triangles_)
      for (uint32_t& v : t) v = h_.old_to_new[v];
    q_.resize(mesh.vertex_count());
  }

  // One attempt with the given smoothing; fills result_.sphere unless cancelled.
  // When give_up_on_folds, an attempt stops at the first level below the finest that
  // ends folded: its insertions fail around the folds and the finer levels rarely
  // recover, so another attempt is cheaper than finishing this one.
  void run(const SmoothingOptions& smoothing, bool give_up_on_folds) {
    smoothing_ = smoothing;
    result_.levels.clear();
    result_.sphere.clear();
    const int levels = static_cast<int>(h_.level_sizes.size());
    int first = projected_start(levels);
    if (first == 0) {
      place_tetrahedron(q_, h_.level_triangles[0]);
      result_.levels.push_back({.vertices = 4});
    }
    for (int l = first + 1; l < levels; ++l) {
      if (session_.should_stop()) {
        result_.stop_reason = session_.stop_reason();
        if (result_.stop_reason == StopReason::kCancelled) return;
        // Out of time: finish the insertions unsmoothed so the map is still complete.
        for (; l < levels; ++l) insert_level(l, result_.levels.emplace_back());
        break;
      }
      // Tiny levels are only inserted: their rings span much of the sphere, where the
      // smoothing throws vertices across it (measured: collapse in 2 iterations at 5
      // vertices) and the fallback leaves the crowding that breaks finer levels.
      if (h_.level_sizes[l] < options_.smooth_min_vertices && l + 1 < levels)
        insert_level(l, result_.levels.emplace_back());
      else
        map_level(l, levels);
      if (give_up_on_folds && l + 1 < levels && result_.levels.back().folds > 0) {
        result_.stop_reason = StopReason::kFoldsRemain;
        result_.sphere.clear();
        return;
      }
    }
    result_.mapping_seconds = session_.elapsed() - result_.hierarchy_seconds;
    if (session_.cancelled()) {
      result_.stop_reason = StopReason::kCancelled;
      return;
    }
    export_sphere();
  }

  // The fine level's faces all weigh 1 from here on (the fills' weights dropped).
  void weigh_every_face_alike() {
    fine_weights_.clear();
    represented_.clear();
  }

  // The stretch-optimized map (ALGORITHM §F): from the tetrahedron, every level is
  // inserted kernel-safe into the optimized map of the level below, then optimized
  // itself, so thin parts are opened while they are a few triangles wide instead of being
  // squeezed and opened by local moves at full resolution. Leaves result_.sphere empty
  // (the caller falls back to the fast map) when a level cannot be made fold-free.
  // relieve_hot_spots: each level's optimization starts by relieving what the insertions
  // squeezed (StretchOptions::relieve_hot_spots).
  void run_optimized(bool relieve_hot_spots) {
    relieve_hot_spots_ = relieve_hot_spots;
    smoothing_ = options_.smoothing;
    result_.levels.clear();
    result_.sphere.clear();
    const int levels = static_cast<int>(h_.level_sizes.size());
    place_tetrahedron(q_, h_.level_triangles[0]);
    result_.levels.push_back({.vertices = 4});
    optimize_level(0, levels);
    for (int l = 1; l < levels; ++l) {
      if (session_.should_stop()) {
        result_.stop_reason = session_.stop_reason();
        if (result_.stop_reason == StopReason::kCancelled) return;
        for (; l < levels; ++l) insert_level(l, result_.levels.emplace_back());
        break;
      }
      LevelReport& report = result_.levels.emplace_back();
      insert_level(l, report);
      if (report.failed_insertions > 0) retry_level(l, report);
      if (report.failed_insertions > 0 && !repair_level(l, levels, report)) {
        result_.stop_reason = StopReason::kFoldsRemain;
        if (!session_.should_stop()) return;
        // Stopped while repairing: the map is finished unrepaired, as at the loop's top.
        result_.stop_reason = session_.stop_reason();
        if (result_.stop_reason == StopReason::kCancelled) return;
        for (++l; l < levels; ++l) insert_level(l, result_.levels.emplace_back());
        break;
      }
      optimize_level(l, levels);
    }
    if (session_.cancelled()) {
      result_.stop_reason = StopReason::kCancelled;
      return;
    }
    export_sphere();
  }

 private:
  // The map in the input's vertex ids.
  void export_sphere() {
    result_.sphere.resize(q_.size());
    for (uint32_t v = 0; v < q_.size(); ++v) result_.sphere[v] = q_[h_.old_to_new[v]];
  }

  std::span<const Triangle> triangles_of(int l, int levels) const {
    return l + 1 == levels ? std::span<const Triangle>(fine_triangles_) : h_.level_triangles[l];
  }

  // Operator A of level l; the finest level uses the input's polygons.
  SparseMatrix operator_of(int l, int levels) const {
    return l + 1 == levels
               ? fine_operator(mesh_, h_.old_to_new, options_.alpha)
               : level_operator(h_.level_triangles[l], h_.level_sizes[l], options_.alpha);
  }

  // Surface positions of the first n vertices (hierarchy ids).
  std::vector<Vec3> positions_of(size_t n) const {
    std::vector<Vec3> x(n);
    for (uint32_t v = 0; v < n; ++v) x[v] = position(v);
    return x;
  }

  // Folds left by failed insertions, removed by the local Lai-Cheng repair. True when
  // the level is fold-free.
  bool repair_level(int l, int levels, LevelReport& report) {
    const size_t n = h_.level_sizes[l];
    std::span<const Triangle> triangles = triangles_of(l, levels);
    LaiChengSmoother smoother(triangles, operator_of(l, levels), n, smoothing_);
    std::span<Vec3> q(q_.data(), n);
    size_t folds = smoother.count_folds(q);
    if (folds > 0) {
      session_.report({.stage = "repair", .level = l, .levels = levels - 1, .vertices = n});
      const RepairStats repair = local_repair(smoother, q, folds, options_.max_repair_iterations,
                                              [&] { return session_.should_stop(); });
      count_repair(repair);
      report.repair_iterations = repair.iterations;
      folds = repair.folds;
    }
    report.folds = folds;
    return folds == 0;
  }

  Vec3 position(uint32_t id) const { return mesh_.positions[h_.new_to_old[id]]; }

  // A third of each triangle's surface area (times its weight, when given) on each of its
  // corners (ids < n).
  std::vector<double> corner_areas(std::span<const Triangle> triangles, size_t n,
                                   std::span<const double> weights = {}) const {
    std::vector<double> area(n, 0);
    for (size_t k = 0; k < triangles.size(); ++k) {
      const Triangle& t = triangles[k];
      const double third =
          norm(cross(position(t[1]) - position(t[0]), position(t[2]) - position(t[0]))) / 6 *
          (weights.empty() ? 1.0 : weights[k]);
      for (uint32_t v : t) area[v] += third;
    }
    return area;
  }

  // The fine surface area each vertex stands for at every level, in one pass from the
  // finest level down: a collapsed vertex's share goes to its ring in equal parts (after
  // the collapse the ring's triangles cover its surface; giving it all to the collapse
  // target made the weights patchy: igea's area distortion 0.106 -> 0.126).
  void compute_represented_areas() {
    const int levels = static_cast<int>(h_.level_sizes.size());
    represented_.assign(levels, {});
    // Filled faces stand for their weighed area (MapOptions::filled_weight) at every level.
    std::vector<double> mass = corner_areas(fine_triangles_, q_.size(), fine_weights_);
    for (int l = levels - 2; l >= 0; --l) {
      for (uint32_t u = h_.level_sizes[l + 1]; u-- > h_.level_sizes[l];) {
        const std::span<const uint32_t> ring = h_.ring(u);
        for (uint32_t w : ring) mass[w] += mass[u] / static_cast<double>(ring.size());
      }
      represented_[l].assign(mass.begin(), mass.begin() + h_.level_sizes[l]);
    }
  }

  // Per triangle of level l: the fine surface area its corners stand for over the area
  // they have at this level. Shortest-edge collapses thin a long limb first, so a coarse
  // limb is a needle with little area of its own: weighed by its own area it would get
  // little room on the sphere, and every finer level would have to push the rest of the
  // map aside by local moves (measured on the stress fingers: stretch 5.3 against 2.7).
  std::vector<double> represented_scale(int l, std::span<const Triangle> triangles) {
    if (represented_.empty()) compute_represented_areas();
    const std::vector<double>& stands_for = represented_[l];
    const std::vector<double> own = corner_areas(triangles, h_.level_sizes[l]);
    std::vector<double> scale(triangles.size());
    for (size_t k = 0; k < triangles.size(); ++k) {
      const Triangle& t = triangles[k];
      const double mine = own[t[0]] + own[t[1]] + own[t[2]];
      const double theirs = stands_for[t[0]] + stands_for[t[1]] + stands_for[t[2]];
      scale[k] = mine > 0 ? theirs / mine : 1.0;
    }
    return scale;
  }

  // Stretch optimization of level l (fold-free on entry; stays so). The finest level gets
  // the quality's sweep budget; coarser ones run to the relative-decrease stop.
  void optimize_level(int l, int levels) {
    const size_t n = h_.level_sizes[l];
    std::span<const Triangle> triangles = triangles_of(l, levels);
    const std::vector<Vec3> x = positions_of(n);
    const std::vector<double> area_scale = l + 1 == levels ? fine_weights_
                                           : !options_.represented_area
                                               ? std::vector<double>{}
                                               : represented_scale(l, triangles);
    StretchOptions stretch = options_.stretch;
    stretch.threads = smoothing_.threads;
    stretch.relieve_hot_spots = relieve_hot_spots_ && options_.stretch.relieve_hot_spots;
    // Newton steps where a factorization is cheap (measured on horse, standard: levels up
    // to 3,000 vertices cost 12% more time; 12,000 cost 2.9x).
    stretch.newton_max_vertices = 3000;
    if (options_.quality == Quality::kHigh) {
      stretch.max_sweeps *= 10;
      stretch.relative_decrease *= 0.1;
      stretch.newton_max_vertices = 20000;
    } else if (options_.quality == Quality::kFast) {
      stretch.relative_decrease *= 10;
      stretch.newton_max_vertices = 1000;
    }
    const double start = session_.elapsed();
    session_.report({.stage = "optimize", .level = l, .levels = levels - 1, .vertices = n});
    const StretchStats stats = optimize_stretch(
        x, triangles, std::span<Vec3>(q_.data(), n), stretch,
        [&] { return session_.should_stop(); }, {}, area_scale);
    result_.optimize_seconds += session_.elapsed() - start;
    result_.stretch_vertex_updates += stats.vertex_updates;
    LevelReport& report = result_.levels.back();
    report.optimize_sweeps = stats.sweeps;
    report.newton_steps = stats.newton_steps;
    report.energy = stats.final_energy;
    report.min_area = check_map(std::span<const Vec3>(q_.data(), n), triangles).min_signed_area;
    session_.report({.stage = "optimize",
                     .level = l,
                     .levels = levels - 1,
                     .vertices = n,
                     .iteration = stats.sweeps,
                     .energy = stats.final_energy});
  }

  // The paper's start (projection + smoothing + local repair) on the largest level of at
  // most projected_start_vertices vertices, then on smaller ones while it fails (a
  // projection folds where the shape is not star-shaped about its centre). The chain
  // starts at the first level that reaches 0 folds. Returns that level, or 0 (start from
  // the tetrahedron). Measured: a long thin tube maps bijectively this way (min area
  // 8.5e-7) where insertions from a tetrahedron squeeze it below 1e-16.
  int projected_start(int levels) {
    int l = levels - 1;
    while (l > 0 && h_.level_sizes[l] > options_.projected_start_vertices) --l;
    for (; l > 0 && (l + 1 == levels || h_.level_sizes[l] >= options_.smooth_min_vertices); --l) {
      if (session_.should_stop()) return 0;
      if (map_projected(l, levels)) return l;
    }
    return 0;
  }

  bool map_projected(int l, int levels) {
    const size_t n = h_.level_sizes[l];
    std::span<const Triangle> triangles = triangles_of(l, levels);
    const ProjectedMap start =
        projected_map(positions_of(n), triangles, operator_of(l, levels), smoothing_,
                      {.iterations = options_.projected_start_iterations}, session_,
                      {.stage = "project", .level = l, .levels = levels - 1, .vertices = n});
    count_work(start.iterations, n);
    count_repair(start.repair);
    if (start.folds > 0) return false;
    std::copy(start.sphere.begin(), start.sphere.end(), q_.begin());
    result_.levels.push_back({.vertices = n,
                              .iterations = start.iterations,
                              .repair_iterations = start.repair.iterations,
                              .min_area = check_map(start.sphere, triangles).min_signed_area});
    return true;
  }

  void insert_level(int l, LevelReport& report) {
    report.vertices = h_.level_sizes[l];
    for (uint32_t u = h_.level_sizes[l - 1]; u < h_.level_sizes[l]; ++u) {
      switch (insert_vertex(q_, u, h_.collapse_target[u], h_.ring(u))) {
        case InsertionOutcome::kRingAverage:
          break;
        case InsertionOutcome::kKernelSearch:
          ++report.kernel_insertions;
          break;
        case InsertionOutcome::kFailed:
          ++report.failed_insertions;
          break;
      }
    }
  }

  // A level whose insertions failed is inserted again with retries; when some still fail,
  // once more from the same start, relieving every squeezed star and not only those a
  // kernel search left. Not the first choice: relieving ring averages too moves more of
  // the map, and on the envelope of 20,000 generated quads (std::mt19937 positions) it
  // left 4 degenerate triangles where the narrower relief certified. The same quads from
  // Python's generator (bench/reach/scatter.py quads 20000) fail 309 insertions of level
  // 11 with the narrower relief, all around one vertex whose ring-averaged star shrank
  // 1e-9 -> 1e-17, and map with this.
  void retry_level(int l, LevelReport& report) {
    const std::vector<Vec3> start(q_.begin(), q_.begin() + h_.level_sizes[l]);
    insert_level_with_retries(l, report, false);
    if (report.failed_insertions == 0 || session_.should_stop()) return;
    std::copy(start.begin(), start.end(), q_.begin());
    insert_level_with_retries(l, report, true);
  }

  // The level's insertions again (the same until the first failure), but a vertex that
  // finds no kernel gets the mesh of the vertices inserted before it stretch-optimized
  // around its ring, then is tried again, and a kernel insertion (any insertion, with
  // relieve_ring_averages) that squeezed its star gets the mesh with it optimized around
  // that star. A thin plate's finest level reopens its whole
  // side band at once (the hierarchy collapsed the thickness first): each twin's kernel is
  // a sliver its neighbour's insertion left, narrower than the fold test's margin, and
  // only moving the neighbours opens it. Only levels with failed insertions run this.
  void insert_level_with_retries(int l, LevelReport& report, bool relieve_ring_averages) {
    report.kernel_insertions = report.failed_insertions = 0;
    PartialLevel partial(h_.level_triangles[l - 1]);
    bool fold_free = true;  // the prefix mesh, so the optimizer may run on it
    StretchOptions stretch = options_.stretch;
    stretch.threads = smoothing_.threads;
    stretch.relieve_hot_spots = false;
    stretch.newton_max_vertices = 0;
    for (uint32_t u = h_.level_sizes[l - 1]; u < h_.level_sizes[l]; ++u) {
      const uint32_t v = h_.collapse_target[u];
      const std::span<const uint32_t> ring = h_.ring(u);
      InsertionOutcome outcome = insert_vertex(q_, u, v, ring);
      if (outcome == InsertionOutcome::kFailed && fold_free && !session_.should_stop()) {
        std::vector<uint32_t> start(ring.begin(), ring.end());
        optimize_stretch(
            positions_of(u), partial.triangles(), std::span<Vec3>(q_.data(), u), stretch,
            [&] { return session_.should_stop(); }, start);
        outcome = insert_vertex(q_, u, v, ring);
      }
      if (outcome == InsertionOutcome::kKernelSearch) ++report.kernel_insertions;
      if (outcome == InsertionOutcome::kFailed) ++report.failed_insertions, fold_free = false;
      partial.split(u, v, ring);
      const bool relieve = outcome == InsertionOutcome::kKernelSearch ||
                           (relieve_ring_averages && outcome == InsertionOutcome::kRingAverage);
      if (relieve && fold_free && !session_.should_stop() && squeezed_star(u, ring)) {
        std::vector<uint32_t> start(ring.begin(), ring.end());
        start.push_back(u);
        optimize_stretch(
            positions_of(u + 1), partial.triangles(), std::span<Vec3>(q_.data(), u + 1), stretch,
            [&] { return session_.should_stop(); }, start);
      }
    }
  }

  // Whether u's star (just inserted, ids <= u) has a triangle below 1e-3 of the mean area
  // of the map so far (about 2 pi / u; the triple product is twice the area). A kernel
  // insertion into a squeezed star leaves a smaller one, where the next insertion of the
  // level often lands: on a thin shell's cut envelope (the beetle's, 20K triangles) one
  // level of 125 vertices went 5.5e-6 -> 4e-18 in 27 insertions, then they failed. Relieved
  // as they come, the map never gets there.
  bool squeezed_star(uint32_t u, std::span<const uint32_t> ring) const {
    const double bound = 1e-3 * 4 * M_PI / static_cast<double>(u + 1);
    for (size_t k = 0; k < ring.size(); ++k)
      if (triple_product(q_[u], q_[ring[k]], q_[ring[(k + 1) % ring.size()]]) < bound) return true;
    return false;
  }

  void map_level(int l, int levels) {
    LevelReport& report = result_.levels.emplace_back();
    insert_level(l, report);
    const size_t n = h_.level_sizes[l];
    std::span<const Triangle> triangles = triangles_of(l, levels);
    LaiChengSmoother smoother(triangles, operator_of(l, levels), n, smoothing_);
    std::span<Vec3> q(q_.data(), n);

    size_t folds = smoother.count_folds(q);
    std::vector<Vec3> fold_free;
    if (folds == 0) fold_free.assign(q.begin(), q.end());
    MapProgress progress{.stage = "smooth", .level = l, .levels = levels - 1, .vertices = n};
    size_t it = 0;
    while (it < options_.max_level_iterations &&
           !(folds == 0 && it >= options_.min_level_iterations)) {
      if (session_.should_stop()) break;
      folds = smoother.step(q);
      ++it;
      if (folds == 0) fold_free.assign(q.begin(), q.end());
      progress.iteration = it, progress.folds = folds;
      session_.report(progress);
    }
    report.iterations = it;
    count_work(it, n);

    if (folds > 0) {
      progress.stage = "repair";
      session_.report(progress);
      RepairStats repair = local_repair(smoother, q, folds, options_.max_repair_iterations,
                                        [&] { return session_.should_stop(); });
      folds = repair.folds;
      report.repair_iterations = repair.iterations;
      count_repair(repair);
    }
    if (folds > 0 && !fold_free.empty()) {
      progress.stage = "fallback";
      session_.report(progress);
      folds = fall_back(smoother, q, fold_free, report);
    }
    report.folds = folds;
    report.min_area = check_map(q, triangles).min_signed_area;
  }

  // From the last fold-free state: fold-safe steps spread the map as far as validity
  // allows, then plain smoothing, kept while it stays fold-free. Returns the folds left
  // (0: the fold-free state is restored otherwise).
  size_t fall_back(LaiChengSmoother& smoother, std::span<Vec3> q, std::vector<Vec3>& fold_free,
                   LevelReport& report) {
    report.fallback = true;
    std::copy(fold_free.begin(), fold_free.end(), q.begin());
    fold_safe_steps(smoother, q, options_.safe_steps, [&] { return session_.should_stop(); });
    count_work(options_.safe_steps, q.size());
    fold_free.assign(q.begin(), q.end());
    for (size_t k = 0; k < options_.max_level_iterations && !session_.should_stop(); ++k) {
      ++report.iterations;
      count_work(1, q.size());
      if (smoother.step(q) > 0) break;
      fold_free.assign(q.begin(), q.end());
    }
    std::copy(fold_free.begin(), fold_free.end(), q.begin());
    return smoother.count_folds(q);
  }

  // Iterations on a level of n vertices, in the totals and in fine-mesh equivalents.
  void count_work(size_t iterations, size_t n) {
    result_.iterations += iterations;
    result_.fine_iteration_equivalents +=
        static_cast<double>(iterations * n) / static_cast<double>(q_.size());
  }

  void count_repair(const RepairStats& repair) {
    result_.iterations += repair.iterations;
    result_.fine_iteration_equivalents += repair.vertex_updates / static_cast<double>(q_.size());
  }

  const PolygonMesh& mesh_;
  const MapSession& session_;
  const MapOptions& options_;
  MapResult& result_;
  CollapseHierarchy h_;
  std::vector<Triangle> fine_triangles_;
  std::vector<double> fine_weights_;  // per fine triangle, empty: 1 each (map_session.h)
  std::vector<Vec3> q_;               // hierarchy ids
  // Per level but the finest: the fine surface area each vertex stands for.
  std::vector<std::vector<double>> represented_;
  SmoothingOptions smoothing_;
  bool relieve_hot_spots_ = true;
};

// The smoothing of each attempt: the caller's first, then the other measured settings
// of the A-step weight w and the offset u. Their order is the corpus's: (w, u) =
// (0.5, 0.25) maps all but beast, (0.5, 0) maps beast (BENCHMARKS.md).
std::vector<SmoothingOptions> attempt_plan(const SmoothingOptions& first, size_t attempts) {
  std::vector<SmoothingOptions> plan{first};
  const std::pair<double, double> alternatives[] = {
      {0.5, 0.25}, {0.5, 0.0}, {1.0, 0.25}, {1.0, 0.0}};
  for (auto [w, u] : alternatives) {
    if (plan.size() >= attempts) break;
    if (w == first.limit_weight && u == first.offset) continue;
    SmoothingOptions next = first;
    next.limit_weight = w, next.offset = u;
    plan.push_back(next);
  }
  return plan;
}

}  // namespace

// The paper's map of the whole mesh with a small budget, before any hierarchy: smooth,
// star-shaped shapes (igea: 10 iterations) need nothing more. Gives up after 10
// iterations when over 0.5% of the triangles are folded. True if it mapped the mesh.
bool map_directly(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                  const MapSession& session, MapResult& result) {
  const MapOptions& options = session.options();
  if (options.direct_iterations == 0) return false;
  const ProjectedMapBudget budget{.iterations = options.direct_iterations,
                                  .repair = true,
                                  .probe_iterations = options.min_level_iterations,
                                  .max_fold_share = 0.005};
  ProjectedMap direct = projected_map(
      mesh.positions, triangles, limit_operator(mesh, options.alpha), options.smoothing, budget,
      session, {.stage = "project", .level = 1, .levels = 1, .vertices = mesh.vertex_count()});
  result.iterations += direct.iterations + direct.repair.iterations;
  result.fine_iteration_equivalents +=
      static_cast<double>(direct.iterations) +
      direct.repair.vertex_updates / static_cast<double>(mesh.vertex_count());
  if (direct.folds > 0 || !verify_map(direct.sphere, triangles, mesh, result.inward).bijective)
    return false;
  result.levels.push_back({.vertices = mesh.vertex_count(),
                           .iterations = direct.iterations,
                           .repair_iterations = direct.repair.iterations,
                           .min_area = check_map(direct.sphere, triangles).min_signed_area});
  result.sphere = std::move(direct.sphere);
  result.mapping_seconds = session.elapsed();
  ++result.attempts;
  return true;
}

void polish_map(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                const MapSession& session, MapResult& result) {
  StretchOptions stretch = session.options().stretch;
  stretch.threads = session.options().smoothing.threads;
  stretch.max_sweeps = 100;
  stretch.relative_decrease = 0;  // the active set decides: the region is small
  for (int round = 0; round < 4 && !session.should_stop(); ++round) {
    const std::vector<uint32_t> start = uncertain_vertices(result.sphere, triangles);
    if (start.empty()) break;
    if (check_map(result.sphere, triangles).folds > 0) return;
    session.report({.stage = "polish", .level = round, .vertices = start.size()});
    const double begin = session.elapsed();
    const StretchStats stats = optimize_stretch(
        mesh.positions, triangles, result.sphere, stretch, [&] { return session.should_stop(); },
        start, session.triangle_weights());
    result.optimize_seconds += session.elapsed() - begin;
    result.stretch_vertex_updates += stats.vertex_updates;
    ++result.polish_rounds;
  }
  // What still fails in float32 (the energy does not mind slivers of next to no area in
  // 3D) is given room by moving corners (float32_rescue.h); a map with nothing failing
  // there, nearly every map, is not changed.
  if (!session.should_stop()) result.float32_rescued += rescue_float32(result.sphere, triangles);
}

namespace {

// A map stopped with no complete map yet (in the hierarchy, or after a failed optimized
// attempt): the mesh's own positions (centred and scaled) projected radially stand in,
// so the caller still gets a complete map, with the stop reason as its verdict (a
// projection is rarely bijective). Cancelled: no map.
void stand_in_map(const PolygonMesh& mesh, const MapSession& session, MapResult& result) {
  result.stop_reason = session.stop_reason();
  result.sphere.clear();
  if (result.stop_reason == StopReason::kCancelled) return;
  result.sphere.reserve(mesh.vertex_count());
  for (const Vec3& p : mesh.positions) result.sphere.push_back(normalized_or(p, Vec3{0, 0, 1}));
}

// Returns true when the map left in result is polished already (an optimized one).
bool map_levels(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                const MapSession& session, MapResult& result) {
  const MapOptions& options = session.options();
  if (options.optimize) {
    CoarseToFine optimized(mesh, triangles, session, result, options.level_growth);
    // With the hot spots relieved first, then (rarely needed) without: the relieved map
    // is 8-20% faster, but the levels come out different, and on one corpus mesh of
    // thirty (beast from Draco) an insertion then fails where the other map's does not.
    // Then, when preparation's fills were weighed down (MapOptions::filled_weight) and
    // neither map came out fold-free with no degenerate triangle, once more with every
    // face weighed alike: a light fill lets the optimizer squeeze a handle's cap to
    // nothing, which the polish cannot always open (PrusaSlicer's aq_bed.stl, 76 handles
    // closed: 5 triangles of about 1e-19 of the sphere, 3 of them folding as the polish
    // pushed; the evenly weighed map is certified). Each map is judged polished, as it
    // will be certified: a map the polish leaves with degenerate triangles goes on to the
    // next variant (the envelope of 20,000 generated quads: 4 triangles below 1e-14 after
    // the relieved map's polish), and the bijective map with the fewest of them is kept
    // and returned when no variant does better.
    const bool weighed = !session.triangle_weights().empty();
    std::optional<MapResult> kept;
    size_t kept_degenerate = 0;
    for (const int variant : {0, 1, 2}) {
      const bool relieve = variant != 1;
      if (variant == 1 && !options.stretch.relieve_hot_spots) continue;
      if (variant == 2) {
        if (!weighed) break;
        optimized.weigh_every_face_alike();
      }
      ++result.attempts;
      result.stop_reason = StopReason::kFoldsRemain;  // the default: a run sets another
      optimized.run_optimized(relieve);
      if (result.stop_reason == StopReason::kCancelled) return false;
      result.optimized = true;
      if (result.sphere.empty()) {
        if (session.should_stop()) break;
        continue;
      }
      polish_map(mesh, triangles, session, result);
      if (result.stop_reason == StopReason::kTimeLimit) return true;
      const MapCheck check = verify_map(result.sphere, triangles, mesh, result.inward);
      if (check.bijective && check.degenerate == 0) return true;
      if (check.bijective && (!kept || check.degenerate < kept_degenerate)) {
        kept = result;
        kept_degenerate = check.degenerate;
      }
      if (session.should_stop()) break;
    }
    if (kept) {
      const size_t attempts = result.attempts;
      result = std::move(*kept);
      result.attempts = attempts;
      return true;
    }
    result.optimized = false;  // what follows is the Lai-Cheng map of each level
    // Out of time: a second hierarchy would only add its own time.
    if (session.should_stop()) {
      if (result.sphere.empty() || session.cancelled())
        stand_in_map(mesh, session, result);
      else
        result.stop_reason = session.stop_reason();
      return false;
    }
  }
  const bool mapped = map_directly(mesh, triangles, session, result);
  if (session.cancelled()) {
    result.stop_reason = StopReason::kCancelled;
    result.sphere.clear();
    return false;
  }
  if (mapped) return false;
  CoarseToFine mapper(mesh, triangles, session, result, 4.0);
  const size_t budget = std::max<size_t>(1, options.attempts);
  const std::vector<SmoothingOptions> plan = attempt_plan(options.smoothing, budget);
  for (size_t k = 0; k < plan.size(); ++k) {
    ++result.attempts;
    // The last attempt this call makes runs to the end, so the caller always gets a full
    // map (the plan can be shorter than the budget: then its last entry is the last).
    const bool last = k + 1 == plan.size() || result.attempts >= budget;
    mapper.run(plan[k], !last);
    if (result.stop_reason == StopReason::kCancelled ||
        result.stop_reason == StopReason::kTimeLimit)
      return false;
    if (!result.sphere.empty() &&
        verify_map(result.sphere, triangles, mesh, result.inward).bijective)
      return false;
    if (last) return false;
  }
  return false;
}

}  // namespace

void map_coarse_to_fine(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                        const MapSession& session, MapResult& result) {
  bool polished = false;
  try {
    polished = map_levels(mesh, triangles, session, result);
  } catch (const HierarchyStopped&) {
    stand_in_map(mesh, session, result);
  }
  if (!polished && result.stop_reason != StopReason::kCancelled)
    polish_map(mesh, triangles, session, result);
}

}  // namespace spheremap
