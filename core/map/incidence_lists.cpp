#include "core/map/incidence_lists.h"

#include <algorithm>

namespace spheremap {

namespace {
// Room for this many more triangles per list at the start: a collapse target gains one or
// two triangles net per collapse, and most vertices are targets a few times at most.
constexpr uint32_t kSlack = 4;
}  // namespace

IncidenceLists::IncidenceLists(size_t vertex_count, std::span<const Triangle> triangles)
    : begin_(vertex_count + 1, 0), size_(vertex_count, 0), capacity_(vertex_count, 0) {
  for (const Triangle& t : triangles)
    for (uint32_t v : t) ++capacity_[v];
  for (size_t v = 0; v < vertex_count; ++v) {
    capacity_[v] += kSlack;
    begin_[v + 1] = begin_[v] + capacity_[v];
  }
  slots_.resize(begin_[vertex_count]);
  begin_.pop_back();
  for (uint32_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t]) slots_[begin_[v] + size_[v]++] = t;
}

void IncidenceLists::append(uint32_t v, uint32_t triangle) {
  if (size_[v] == capacity_[v]) {  // move the list to the end, with twice the room
    const uint64_t moved = slots_.size();
    capacity_[v] *= 2;
    slots_.resize(moved + capacity_[v]);
    std::copy_n(slots_.begin() + static_cast<std::ptrdiff_t>(begin_[v]), size_[v],
                slots_.begin() + static_cast<std::ptrdiff_t>(moved));
    begin_[v] = moved;
  }
  slots_[begin_[v] + size_[v]++] = triangle;
}

void IncidenceLists::erase(uint32_t v, uint32_t triangle) {
  uint32_t* first = slots_.data() + begin_[v];
  uint32_t* last = first + size_[v];
  uint32_t* found = std::find(first, last, triangle);
  if (found == last) return;
  std::copy(found + 1, last, found);
  --size_[v];
}

}  // namespace spheremap
