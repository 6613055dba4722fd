#include "core/map/certification.h"

namespace spheremap {
namespace {

std::string counts(const MapCheck& check) {
  return std::to_string(check.folds) + " folded triangles left and " +
         std::to_string(check.degenerate) + " degenerate";
}

}  // namespace

Certification certify(const MappedMesh& mapped, const MapCheck& written) {
  const MapResult& map = mapped.map;
  if (map.stop_reason == StopReason::kTimeLimit)
    return {
        false, "time_limit",
        "the map stopped at the time limit" +
            (map.stopped_in.empty() ? std::string() : " during its " + map.stopped_in + " stage") +
            " with " + counts(map.check) +
            " (the map returned is complete but not optimized to the end)"};
  if (!clean(map.check)) {
    std::string detail = "no bijective map reached (" + std::string(to_string(map.stop_reason)) +
                         "): " + counts(map.check);
    if (map.attempts > 0) detail += " after " + std::to_string(map.attempts) + " attempts";
    if (map.check.folds == 0 && map.check.degenerate == 0 && !map.check.bijective)
      detail += "; the signed areas sum to " + std::to_string(map.check.signed_area_sum) +
                ", not 4 pi: the map covers the sphere more than once";
    return {false, "not_bijective", detail};
  }
  if (!clean(mapped.float32_check))
    return {false, "not_bijective",
            "the map is bijective in double precision, but rounded to float32 it has " +
                counts(mapped.float32_check)};
  if (!clean(written))
    return {false, "not_bijective",
            "the map is bijective in double and float32, but as written (quantized) it has " +
                counts(written) + "; use more Draco position bits or no Draco"};
  return {true, "", ""};
}

}  // namespace spheremap
