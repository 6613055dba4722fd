#include "core/map/certification.h"

namespace spheremap {
namespace {

std::string counts(const MapCheck& check) {
  return std::to_string(check.folds) + " folded triangles left and " +
         std::to_string(check.degenerate) + " degenerate";
}

// The counts, and when neither explains the verdict, the signed area that does.
std::string what_fails(const MapCheck& check) {
  std::string out = counts(check);
  if (check.folds == 0 && check.degenerate == 0 && !check.bijective)
    out += "; the signed areas sum to " + std::to_string(check.signed_area_sum) +
           ", not 4 pi per sphere: the map covers a sphere more than once or not at all";
  return out;
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
                         "): " + what_fails(map.check);
    if (map.attempts > 0) detail += " after " + std::to_string(map.attempts) + " attempts";
    return {false, "not_bijective", detail};
  }
  if (!clean(mapped.float32_check))
    return {false, "not_bijective",
            "the map is bijective in double precision, but rounded to float32 it has " +
                what_fails(mapped.float32_check)};
  if (!clean(written))
    return {
        false, "not_bijective",
        "the map is bijective in double and float32, but as written it has " + what_fails(written)};
  return {true, "", ""};
}

}  // namespace spheremap
