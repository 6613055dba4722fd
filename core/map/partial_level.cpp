#include "core/map/partial_level.h"

#include <stdexcept>

namespace spheremap {
namespace {

// The triangle rotated to start at its smallest vertex (orientation kept).
Triangle key(const Triangle& t) {
  const int k = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

}  // namespace

PartialLevel::PartialLevel(std::span<const Triangle> coarser)
    : triangles_(coarser.begin(), coarser.end()) {
  for (uint32_t t = 0; t < triangles_.size(); ++t) index_[key(triangles_[t])] = t;
}

void PartialLevel::split(uint32_t u, uint32_t v, std::span<const uint32_t> ring) {
  for (size_t k = 0; k < ring.size(); ++k) {
    const uint32_t a = ring[k], b = ring[(k + 1) % ring.size()];
    const Triangle star{u, a, b};
    if (a == v || b == v) {
      index_[key(star)] = static_cast<uint32_t>(triangles_.size());
      triangles_.push_back(star);
      continue;
    }
    const auto it = index_.find(key({v, a, b}));
    if (it == index_.end()) throw std::logic_error("partial level: a ring triangle is missing");
    const uint32_t t = it->second;
    index_.erase(it);
    triangles_[t] = star;
    index_[key(star)] = t;
  }
}

}  // namespace spheremap
