// The one verdict every front end reports (ALGORITHM §B1, engine v2 §4): a map is
// certified only when it ran to the end (no time limit hit) and has no folded and no
// degenerate triangle (spherical area below kDegenerateArea) in double precision, after
// rounding to float32, and as written (the output file decoded again: float32, and
// Draco-quantized for Draco outputs). The CLI exits 0 and a job succeeds only then.
#pragma once

#include <string>

#include "core/map/pipeline.h"

namespace spheremap {

struct Certification {
  bool certified = false;
  std::string problem;  // empty when certified, else "time_limit" or "not_bijective"
  std::string detail;   // the check that failed, with its counts
};

// `written`: the map as a reader sees it; mapped.float32_check when nothing was written.
Certification certify(const MappedMesh& mapped, const MapCheck& written);

// Whether a check passes: no fold, no degenerate triangle, areas summing to 4 pi.
inline bool clean(const MapCheck& check) {
  return check.bijective && check.degenerate == 0;
}

}  // namespace spheremap
