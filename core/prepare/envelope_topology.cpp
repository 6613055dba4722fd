#include "core/prepare/envelope_topology.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <unordered_map>

#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

struct Tables {
  std::array<uint32_t, 27> adjacent26{}, adjacent6{};
  uint32_t n18 = 0, faces = 0;
  std::array<std::array<int, 8>, 8> block_bits{};  // per 2x2x2 cube around the centre
  std::array<uint8_t, 256> critical{};             // per 2x2x2 configuration

  Tables() {
    const auto bit = [](int dx, int dy, int dz) { return (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1); };
    for (int k = 0; k < 27; ++k) {
      const int kx = k % 3 - 1, ky = k / 3 % 3 - 1, kz = k / 9 - 1;
      const int nonzero = (kx != 0) + (ky != 0) + (kz != 0);
      if (k != kCentreBit && nonzero <= 2) n18 |= 1u << k;
      if (nonzero == 1) faces |= 1u << k;
      for (int j = 0; j < 27; ++j) {
        if (j == k || j == kCentreBit || k == kCentreBit) continue;
        const int dx = std::abs(j % 3 - 1 - kx), dy = std::abs(j / 3 % 3 - 1 - ky),
                  dz = std::abs(j / 9 - 1 - kz);
        if (std::max({dx, dy, dz}) == 1) adjacent26[k] |= 1u << j;
        if (dx + dy + dz == 1) adjacent6[k] |= 1u << j;
      }
    }
    for (int b = 0; b < 8; ++b) {
      const int ox = b & 1, oy = (b >> 1) & 1, oz = (b >> 2) & 1;  // the cube spans ox-1..ox
      for (int c = 0; c < 8; ++c)
        block_bits[b][c] = bit(ox - 1 + (c & 1), oy - 1 + ((c >> 1) & 1), oz - 1 + ((c >> 2) & 1));
    }
    for (int m = 0; m < 256; ++m) {
      const auto on = [&](int c) { return (m >> c) & 1; };
      bool bad = false;
      // The six faces of the cube, each as its corners a b / c d with a-d and b-c diagonal.
      for (const auto& f : {std::array{0, 1, 2, 3}, std::array{4, 5, 6, 7}, std::array{0, 1, 4, 5},
                            std::array{2, 3, 6, 7}, std::array{0, 2, 4, 6}, std::array{1, 3, 5, 7}})
        bad |= on(f[0]) == on(f[3]) && on(f[1]) == on(f[2]) && on(f[0]) != on(f[1]);
      const int count = std::popcount(unsigned(m));
      const int odd = count == 2 ? m : (count == 6 ? (~m & 255) : 0);
      for (int c = 0; c < 4; ++c) bad |= odd == ((1 << c) | (1 << (7 - c)));
      critical[m] = bad;
    }
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

// Connected groups of `set` under `adjacent`; with `touch` non-zero only those meeting it.
int groups(uint32_t set, const std::array<uint32_t, 27>& adjacent, uint32_t touch) {
  int count = 0;
  while (set) {
    uint32_t group = set & (~set + 1), front = group;
    while (front) {
      uint32_t grown = 0;
      for (uint32_t f = front; f; f &= f - 1) grown |= adjacent[std::countr_zero(f)];
      front = grown & set & ~group;
      group |= front;
    }
    set &= ~group;
    if (!touch || (group & touch)) ++count;
  }
  return count;
}

}  // namespace

bool is_simple_point(uint32_t neighbourhood) {
  const Tables& t = tables();
  const uint32_t all = (1u << 27) - 1, set = neighbourhood & all & ~(1u << kCentreBit);
  if (groups(set, t.adjacent26, 0) != 1) return false;
  return groups(~neighbourhood & t.n18, t.adjacent6, t.faces) == 1;
}

bool stays_well_composed(uint32_t neighbourhood) {
  const Tables& t = tables();
  const uint32_t with_centre = neighbourhood | (1u << kCentreBit);
  for (const auto& cube : t.block_bits) {
    unsigned m = 0;
    for (int c = 0; c < 8; ++c) m |= ((with_centre >> cube[c]) & 1u) << c;
    if (t.critical[m]) return false;
  }
  return true;
}

namespace {

// Per voxel as the callers set it: bit 1 in the region, bit 2 may join it; run() adds
// bit 8 on the grid's border (never joins).
constexpr uint8_t kIn = 1, kAllowed = 2, kBorder = 8;

// Per voxel one bit (bit i % 8 of byte i / 8, 8 bytes of padding for unaligned loads).
struct Bits {
  std::vector<uint8_t> bytes;
  explicit Bits(size_t n) : bytes(n / 8 + 9, 0) {}
  bool get(size_t i) const { return (bytes[i >> 3] >> (i & 7)) & 1u; }
  void set(size_t i) { bytes[i >> 3] |= uint8_t(1u << (i & 7)); }
  void clear(size_t i) { bytes[i >> 3] &= uint8_t(~(1u << (i & 7))); }
  uint32_t three(size_t i) const {  // bits i, i + 1, i + 2
    uint64_t word;
    std::memcpy(&word, &bytes[i >> 3], sizeof word);
    return uint32_t((word >> (i & 7)) & 7u);
  }
};

struct Growth {
  const VoxelGrid& g;
  std::vector<uint8_t> state;  // set by the caller, read by run() (then released)
  // The growth itself works on two bits per voxel: in the region, and open (may join, off
  // the border, not in, not queued). A neighbourhood is 9 rows of 3 bits, one unaligned
  // load each, and so are the neighbours to queue: 27 byte loads over 3 planes of a byte
  // per voxel cost a fifth of the growth, the queue's byte per neighbour another sixth.
  Bits in, open;
  std::array<std::ptrdiff_t, 9> row{};  // per row dy + 3 dz of the 3x3x3: its dx = -1 voxel

  explicit Growth(const VoxelGrid& grid)
      : g(grid), state(grid.size(), 0), in(grid.size()), open(grid.size()) {
    for (int r = 0; r < 9; ++r)
      row[size_t(r)] = -1 + (r % 3 - 1) * std::ptrdiff_t(g.nx) +
                       (r / 3 - 1) * std::ptrdiff_t(g.nx) * std::ptrdiff_t(g.ny);
  }
  // Sets kBorder on the voxels of the grid's six border faces.
  void mark_border() {
    for (int z = 0; z < g.nz; ++z)
      for (int y = 0; y < g.ny; ++y) {
        const bool face = z == 0 || y == 0 || z == g.nz - 1 || y == g.ny - 1;
        for (int x = 0; x < g.nx; ++x)
          if (face || x == 0 || x == g.nx - 1) state[g.index(x, y, z)] |= kBorder;
      }
  }
  // Only for voxels off the grid's border (candidates never lie on it). Bit k of the
  // answer is the voxel at offset (k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1).
  uint32_t neighbourhood(size_t i) const {
    uint32_t m = 0;
    for (int r = 0; r < 9; ++r)
      m |= in.three(size_t(std::ptrdiff_t(i) + row[size_t(r)])) << (3 * r);
    return m;
  }

  // Whether a voxel with this neighbourhood may join: simple and well-composed. Answers
  // are remembered in a direct-mapped table (the same few thousand neighbourhoods recur
  // along a flat front; the outside growth asks for millions of voxels). A slot holds the
  // key plus 1 (0: empty; keys have 27 bits) and the answer in bit 31.
  static constexpr int kAnswerBits = 16;
  std::vector<uint32_t> answers = std::vector<uint32_t>(size_t{1} << kAnswerBits, 0);
  bool may_join(uint32_t m) {
    const uint32_t key = m & ~(1u << kCentreBit);
    uint32_t& slot = answers[(key * 2654435761u) >> (32 - kAnswerBits)];
    if ((slot & ~(1u << 31)) == key + 1) return slot >> 31;
    const bool yes = is_simple_point(key) && stays_well_composed(key);
    slot = (key + 1) | (uint32_t(yes) << 31);
    return yes;
  }

  // Grows from the voxels already in, highest priority first (a bucket queue; within a
  // bucket last in, first out). The queue order is that of a walk over the voxels in
  // index order, then over each joined voxel's 27 neighbours in bit order.
  void run(const std::vector<uint16_t>& priority, StopCheck& stop) {
    mark_border();
    for (size_t i = 0; i < state.size(); ++i) {
      if (state[i] & kIn) in.set(i);
      if ((state[i] & (kIn | kAllowed | kBorder)) == kAllowed) open.set(i);
    }
    const size_t voxels = state.size();
    state = {};
    std::vector<std::vector<uint32_t>> buckets(65536);
    int top = -1;
    const auto push = [&](size_t j) {  // j is open
      open.clear(j);
      buckets[priority[j]].push_back(uint32_t(j));
      top = std::max(top, int(priority[j]));
    };
    // The open voxels with a neighbour in, in index order (a word of open bits at a time).
    for (size_t byte = 0; byte * 8 < voxels; byte += 8) {
      uint64_t word;
      std::memcpy(&word, &open.bytes[byte], sizeof word);
      for (; word; word &= word - 1) {
        const size_t i = byte * 8 + size_t(std::countr_zero(word));
        if (i < voxels && neighbourhood(i) != 0) push(i);
      }
    }
    while (top >= 0) {
      if (buckets[size_t(top)].empty()) {
        --top;
        continue;
      }
      const size_t i = buckets[size_t(top)].back();
      buckets[size_t(top)].pop_back();
      stop.tick();
      // The neighbours' priorities are read if it joins: fetched while it is decided.
      for (int r = 0; r < 9; ++r)
        __builtin_prefetch(&priority[size_t(std::ptrdiff_t(i) + row[size_t(r)])]);
      if (!may_join(neighbourhood(i))) {
        open.set(i);  // no longer queued: a later neighbour may queue it again
        continue;
      }
      in.set(i);
      for (int r = 0; r < 9; ++r) {
        const size_t j = size_t(std::ptrdiff_t(i) + row[size_t(r)]);
        const uint32_t bits = open.three(j);
        if (bits & 1u) push(j);
        if (bits & 2u) push(j + 1);
        if (bits & 4u) push(j + 2);
      }
    }
  }
};

// Calls visit(j) for each 26-neighbour j of voxel v inside the grid.
template <typename Visit>
void for_each_neighbour(const VoxelGrid& g, size_t v, Visit visit) {
  const int x = int(v % size_t(g.nx)), y = int(v / size_t(g.nx) % size_t(g.ny)),
            z = int(v / (size_t(g.nx) * size_t(g.ny)));
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int a = x + dx, b = y + dy, c = z + dz;
        if (a < 0 || b < 0 || c < 0 || a >= g.nx || b >= g.ny || c >= g.nz) continue;
        visit(g.index(a, b, c));
      }
}

// Counts the changed voxels and their 26-connected groups.
void count_changes(const VoxelGrid& g, const std::vector<uint8_t>& solid, BallGrowth& out,
                   StopCheck& stop) {
  std::vector<uint8_t> seen(g.size(), 0);
  std::vector<uint32_t> stack;
  for (size_t i = 0; i < g.size(); ++i) {
    stop.tick();
    if (seen[i] || solid[i] == out.ball[i]) continue;
    size_t group = 0;
    seen[i] = 1, stack.push_back(uint32_t(i));
    while (!stack.empty()) {
      const size_t v = stack.back();
      stack.pop_back();
      ++group;
      for_each_neighbour(g, v, [&](size_t j) {
        if (!seen[j] && solid[j] != out.ball[j]) seen[j] = 1, stack.push_back(uint32_t(j));
      });
    }
    out.voxels_changed += group;
    ++out.changes;
    out.largest_change = std::max(out.largest_change, group);
  }
}

// The 26-connected groups of the voxels where solid and ball differ: per such voxel its
// group (a map: the changes are few against the grid), and each group's size.
struct ChangeGroups {
  std::unordered_map<uint32_t, uint32_t> group_of;
  std::vector<size_t> sizes;
};

ChangeGroups change_groups(const VoxelGrid& g, const std::vector<uint8_t>& solid,
                           const std::vector<uint8_t>& ball, StopCheck& stop) {
  ChangeGroups out;
  std::vector<uint32_t> stack;
  for (size_t i = 0; i < g.size(); ++i) {
    stop.tick();
    if (solid[i] == ball[i] || out.group_of.count(uint32_t(i))) continue;
    const uint32_t id = uint32_t(out.sizes.size());
    out.sizes.push_back(0);
    out.group_of[uint32_t(i)] = id, stack.push_back(uint32_t(i));
    while (!stack.empty()) {
      const size_t v = stack.back();
      stack.pop_back();
      ++out.sizes[id];
      for_each_neighbour(g, v, [&](size_t j) {
        if (solid[j] != ball[j] && out.group_of.emplace(uint32_t(j), id).second)
          stack.push_back(uint32_t(j));
      });
    }
  }
  return out;
}

}  // namespace

BallGrowth grow_ball_mixed(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                           const BallGrowth& cut, const BallGrowth& filled, size_t* fills_kept,
                           StopCheck& stop) {
  const ChangeGroups cuts = change_groups(grid, solid, cut.ball, stop);
  const ChangeGroups fills = change_groups(grid, solid, filled.ball, stop);
  // Per fill group, the voxels of the cut groups it touches (each counted once).
  std::vector<size_t> touched_cut(fills.sizes.size(), 0);
  std::vector<std::vector<uint32_t>> touched(fills.sizes.size());
  for (const auto& entry : fills.group_of) {
    // Plain copies: clang 14 (the fuzzers' compiler) cannot capture structured bindings.
    const uint32_t voxel = entry.first, group = entry.second;
    stop.tick();
    for_each_neighbour(grid, voxel, [&](size_t j) {
      const auto found = cuts.group_of.find(uint32_t(j));
      if (found == cuts.group_of.end()) return;
      std::vector<uint32_t>& list = touched[group];
      if (std::find(list.begin(), list.end(), found->second) != list.end()) return;
      list.push_back(found->second);
      touched_cut[group] += cuts.sizes[found->second];
    });
  }
  std::vector<uint8_t> with_fills = solid;
  size_t kept = 0;
  std::vector<char> keep(fills.sizes.size());
  for (size_t k = 0; k < keep.size(); ++k) {
    keep[k] = fills.sizes[k] < touched_cut[k];
    kept += keep[k];
  }
  for (const auto& [voxel, group] : fills.group_of)
    if (keep[group]) with_fills[voxel] = 1;
  if (fills_kept) *fills_kept = kept;
  BallGrowth out = grow_ball_inside(grid, with_fills, stop);
  out.voxels_changed = out.changes = out.largest_change = 0;
  count_changes(grid, solid, out, stop);
  return out;
}

BallGrowth grow_ball_inside(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                            StopCheck& stop) {
  const std::vector<uint16_t> depth = steps_to_other(grid, solid, 1, stop);
  const size_t deepest = size_t(std::max_element(depth.begin(), depth.end()) - depth.begin());
  if (!solid[deepest]) throw InputError("envelope_empty", "the envelope's solid is empty");
  Growth growth(grid);
  for (size_t i = 0; i < solid.size(); ++i) growth.state[i] = solid[i] ? kAllowed : 0;
  growth.state[deepest] |= kIn;
  growth.run(depth, stop);
  BallGrowth out;
  out.ball.resize(solid.size());
  for (size_t i = 0; i < solid.size(); ++i) out.ball[i] = growth.in.get(i);
  count_changes(grid, solid, out, stop);
  return out;
}

BallGrowth shrink_ball_outside(const VoxelGrid& grid, const std::vector<uint8_t>& solid,
                               StopCheck& stop) {
  const std::vector<uint16_t> distance = steps_to_other(grid, solid, 0, stop);
  Growth growth(grid);
  // The border in (run() marks it kBorder), the rest of the outside allowed.
  for (size_t i = 0; i < solid.size(); ++i) growth.state[i] = solid[i] ? 0 : kAllowed;
  growth.mark_border();
  for (uint8_t& s : growth.state)
    if (s & kBorder) s = kIn | kBorder;
  growth.run(distance, stop);
  BallGrowth out;
  out.ball.resize(solid.size());
  for (size_t i = 0; i < solid.size(); ++i) out.ball[i] = !growth.in.get(i);
  count_changes(grid, solid, out, stop);
  return out;
}

}  // namespace spheremap
