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
  if (size_[v] == capacity_[v]) move_to_end(v);
  slots_[begin_[v] + size_[v]++] = triangle;
}

// Moves v's list to the array's end with twice the room, compacting the array first when
// it has no room left (after which v's list has room where it is).
void IncidenceLists::move_to_end(uint32_t v) {
  const uint32_t room = std::max(2 * capacity_[v], kSlack);
  if (slots_.size() + room > slots_.capacity()) {
    compact(room);
    if (size_[v] < capacity_[v]) return;
  }
  const uint64_t moved = slots_.size();
  slots_.resize(moved + room);
  std::copy_n(slots_.begin() + static_cast<std::ptrdiff_t>(begin_[v]), size_[v],
              slots_.begin() + static_cast<std::ptrdiff_t>(moved));
  begin_[v] = moved, capacity_[v] = room;
}

// Every non-empty list rewritten in vertex order with room for half as many again (at
// least kSlack: a growing fan's list must not lose the room doubling gave it, or a vertex
// gaining thousands of triangles would compact the array every few appends), into an
// array with room for a quarter as many again (at least `extra`) for the lists that move
// next: each compaction costs one pass over the lists, and the next one waits until a
// quarter of them has moved, so appends stay amortized O(1).
void IncidenceLists::compact(uint64_t extra) {
  auto room_for = [](uint32_t size) { return size + std::max(kSlack, size / 2); };
  uint64_t live = 0;
  for (size_t v = 0; v < size_.size(); ++v)
    if (size_[v] > 0) live += room_for(size_[v]);
  std::vector<uint32_t> fresh;
  fresh.reserve(live + std::max(extra, live / 4));
  for (size_t v = 0; v < size_.size(); ++v) {
    const uint64_t begin = fresh.size();
    if (size_[v] > 0) {
      const auto first = slots_.begin() + static_cast<std::ptrdiff_t>(begin_[v]);
      fresh.insert(fresh.end(), first, first + size_[v]);
      fresh.resize(begin + room_for(size_[v]));
    }
    begin_[v] = begin;
    capacity_[v] = size_[v] > 0 ? room_for(size_[v]) : 0;
  }
  slots_.swap(fresh);
  ++compactions_;
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
