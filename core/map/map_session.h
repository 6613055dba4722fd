// Shared plumbing of the mapping methods: clock, stop checks, progress reports.
#pragma once

#include <chrono>
#include <span>
#include <string>

#include "core/map/spherical_map.h"

namespace spheremap {

class MapSession {
 public:
  // `limit_start`: when the time limit started counting (the caller's clock, or the
  // first vertex order's: a second order does not get a fresh budget). elapsed() and the
  // stage timings count from now.
  MapSession(const MapOptions& options, const MapControl& control,
             std::chrono::steady_clock::time_point limit_start)
      : options_(options),
        control_(control),
        start_(std::chrono::steady_clock::now()),
        limit_start_(limit_start) {}

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool cancelled() const { return control_.cancel && control_.cancel->load(); }
  bool timed_out() const {
    return options_.time_limit_seconds > 0 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - limit_start_).count() >
               options_.time_limit_seconds;
  }
  // The first time it says true, the stage last reported is kept: the verdict names it.
  bool should_stop() const {
    const bool stop = cancelled() || timed_out();
    if (stop && stopped_in_.empty()) stopped_in_ = stage_;
    return stop;
  }
  // The stage that was running when the map was first told to stop ("" if never).
  const std::string& stopped_in() const { return stopped_in_; }
  StopReason stop_reason() const {
    return cancelled() ? StopReason::kCancelled : StopReason::kTimeLimit;
  }
  void report(MapProgress progress) const {
    if (stage_ != progress.stage) stage_ = progress.stage;
    if (!control_.on_progress) return;
    progress.elapsed_seconds = elapsed();
    control_.on_progress(progress);
  }
  const MapOptions& options() const { return options_; }
  // Per triangle of the mesh being mapped (the order the method gets them): the factor on
  // its area in the stretch energy (empty: 1 each); faces preparation added weigh less.
  std::span<const double> triangle_weights() const { return triangle_weights_; }
  void set_triangle_weights(std::span<const double> weights) { triangle_weights_ = weights; }

 private:
  std::span<const double> triangle_weights_;
  const MapOptions& options_;
  const MapControl& control_;
  std::chrono::steady_clock::time_point start_, limit_start_;
  mutable std::string stage_ = "start", stopped_in_;
};

// The two methods; both fill result.sphere (input vertex order) and result.stop_reason
// (kCancelled/kTimeLimit/kIterationLimit, or left for the driver's verdict).
void map_paper(const PolygonMesh& mesh, std::span<const Triangle> triangles,
               const MapSession& session, MapResult& result);
void map_coarse_to_fine(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                        const MapSession& session, MapResult& result);

// The safety net before the verdict: triangles of a fold-free map that a reader could not
// tell from a fold (uncertain_vertices) are opened by stretch optimization around them,
// a few rounds. Leaves a folded map as it is.
void polish_map(const PolygonMesh& mesh, std::span<const Triangle> triangles,
                const MapSession& session, MapResult& result);

}  // namespace spheremap
