// Per-vertex lists of incident triangles in one array, for the collapse hierarchy.
//
// A vector of vectors put every vertex's list in a heap block of its own, and the lists
// that grow (collapse targets) were moved by the allocator to wherever it had room: the
// hierarchy reads a star per candidate and per re-keyed vertex, so those reads chased
// pointers across the heap. Here each list is a slice of one array, in vertex order, with
// room for a few more triangles; a list that outgrows its slice moves to the array's end
// with twice the room. When the array is full, it is compacted instead of grown: the
// non-empty lists are rewritten in vertex order with a little room each, which drops the
// slices that moved lists left behind and those of collapsed vertices (grown by doubling,
// the array was the hierarchy's largest allocation at 17M triangles: twice its first
// size, three times while being copied). Lists keep their order (erase shifts, append
// goes last), which the hierarchy's tie-breaking depends on: the same operations give the
// same lists as the vector of vectors did.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/mesh.h"

namespace spheremap {

class IncidenceLists {
 public:
  // The triangles of each of `vertex_count` vertices, in triangle order.
  IncidenceLists(size_t vertex_count, std::span<const Triangle> triangles);

  // A view that stays valid until the next append (which may move the array).
  std::span<const uint32_t> operator[](uint32_t v) const {
    return {slots_.data() + begin_[v], size_[v]};
  }
  size_t size(uint32_t v) const { return size_[v]; }
  uint32_t at(uint32_t v, size_t k) const { return slots_[begin_[v] + k]; }
  bool empty(uint32_t v) const { return size_[v] == 0; }

  void append(uint32_t v, uint32_t triangle);
  void erase(uint32_t v, uint32_t triangle);  // the first occurrence, order kept
  void clear(uint32_t v) { size_[v] = 0; }

  // Slots the array holds (lists, their room, and the slices left behind), and the
  // compactions so far: for tests of the array's bound and of amortized appends.
  size_t slot_count() const { return slots_.size(); }
  size_t compaction_count() const { return compactions_; }

 private:
  void move_to_end(uint32_t v);
  void compact(uint64_t extra);

  std::vector<uint32_t> slots_;
  std::vector<uint64_t> begin_;  // 64-bit: moved lists may take the array past 4G slots
  std::vector<uint32_t> size_, capacity_;
  size_t compactions_ = 0;
};

}  // namespace spheremap
