// Shared plumbing of the mapping methods: clock, stop checks, progress reports.
#pragma once

#include <chrono>

#include "core/map/spherical_map.h"

namespace spheremap {

class MapSession {
 public:
  MapSession(const MapOptions& options, const MapControl& control)
      : options_(options), control_(control), start_(std::chrono::steady_clock::now()) {}

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool cancelled() const { return control_.cancel && control_.cancel->load(); }
  bool timed_out() const {
    return options_.time_limit_seconds > 0 && elapsed() > options_.time_limit_seconds;
  }
  bool should_stop() const { return cancelled() || timed_out(); }
  StopReason stop_reason() const {
    return cancelled() ? StopReason::kCancelled : StopReason::kTimeLimit;
  }
  void report(MapProgress progress) const {
    if (!control_.on_progress) return;
    progress.elapsed_seconds = elapsed();
    control_.on_progress(progress);
  }
  const MapOptions& options() const { return options_; }

 private:
  const MapOptions& options_;
  const MapControl& control_;
  std::chrono::steady_clock::time_point start_;
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
