#include "core/prepare/vertex_copies.h"

#include <algorithm>
#include <numeric>

namespace spheremap {

void insert_vertex_copies(PolygonMesh& input, GltfAppearance* look,
                          const std::vector<uint32_t>& source,
                          std::vector<uint32_t>& input_to_welded) {
  const uint32_t n = static_cast<uint32_t>(input.vertex_count());
  const uint32_t copies = static_cast<uint32_t>(source.size());
  if (copies == 0) return;
  // Where each copy goes: before old vertex `at[k]` (the end of its source's primitive).
  std::vector<uint32_t> at(copies, n);
  if (look)
    for (uint32_t k = 0; k < copies; ++k)
      for (const GltfAppearance::Primitive& p : look->primitives)
        if (source[k] >= p.first_vertex && source[k] - p.first_vertex < p.vertex_count) {
          at[k] = p.first_vertex + p.vertex_count;
          break;
        }
  std::vector<uint32_t> order(copies);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return at[a] < at[b]; });
  // Copies placed before old vertex u: those at or before it.
  std::vector<uint32_t> before(n + 1, 0);
  for (uint32_t k = 0; k < copies; ++k) ++before[at[k]];
  for (uint32_t u = 0; u < n; ++u) before[u + 1] += before[u];
  std::vector<uint32_t> new_id(n + copies);
  for (uint32_t u = 0; u < n; ++u) new_id[u] = u + before[u];
  for (uint32_t rank = 0; rank < copies; ++rank) new_id[n + order[rank]] = at[order[rank]] + rank;
  std::vector<uint32_t> old_of(n + copies);  // new -> old (old >= n: copy old - n)
  for (uint32_t v = 0; v < n + copies; ++v) old_of[new_id[v]] = v;
  auto source_of = [&](uint32_t old) { return old < n ? old : source[old - n]; };

  std::vector<Vec3> positions(n + copies);
  std::vector<uint32_t> to_welded(n + copies);
  for (uint32_t v = 0; v < n + copies; ++v) {
    positions[v] = input.positions[source_of(old_of[v])];
    to_welded[v] = input_to_welded[old_of[v]];
  }
  input.positions = std::move(positions);
  input_to_welded = std::move(to_welded);
  for (uint32_t& v : input.indices) v = new_id[v];
  if (!look) return;
  for (GltfAppearance::Attribute& a : look->attributes) {
    const size_t c = static_cast<size_t>(a.components);
    if (a.values.size() != c * n) continue;
    std::vector<float> values(c * (n + copies));
    for (uint32_t v = 0; v < n + copies; ++v)
      std::copy_n(a.values.begin() + static_cast<std::ptrdiff_t>(c * source_of(old_of[v])), c,
                  values.begin() + static_cast<std::ptrdiff_t>(c * v));
    a.values = std::move(values);
  }
  for (GltfAppearance::Primitive& p : look->primitives) {
    uint32_t inside = 0;
    for (uint32_t k = 0; k < copies; ++k)
      inside += at[k] == p.first_vertex + p.vertex_count && source[k] >= p.first_vertex &&
                source[k] - p.first_vertex < p.vertex_count;
    p.first_vertex = p.first_vertex >= n ? p.first_vertex + copies : new_id[p.first_vertex];
    p.vertex_count += inside;
  }
}

}  // namespace spheremap
