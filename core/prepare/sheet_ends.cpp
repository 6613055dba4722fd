#include "core/prepare/sheet_ends.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace spheremap {

EdgePairs pair_sheets_ending_on_edges(const PolygonMesh& mesh, const StopCheck* stop) {
  const std::vector<EdgeCorner> corners = sorted_edge_corners(mesh, stop);
  UnionFind sheets = manifold_sheets(corners, static_cast<uint32_t>(mesh.face_count()));
  EdgePairs pairs;
  std::vector<std::pair<uint32_t, uint32_t>> by_sheet;  // (sheet, face)
  for (size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].edge == corners[i].edge) ++j;
    if (j - i <= 2) continue;
    by_sheet.clear();
    for (size_t k = i; k < j; ++k)
      by_sheet.push_back({sheets.find(corners[k].face), corners[k].face});
    std::sort(by_sheet.begin(), by_sheet.end());
    bool ends = false, fits = true;
    std::vector<std::pair<uint32_t, uint32_t>> edge_pairs;
    for (size_t a = 0, b = 0; a < by_sheet.size() && fits; a = b) {
      while (b < by_sheet.size() && by_sheet[b].first == by_sheet[a].first) ++b;
      if (b - a == 1) {
        ends = true;
      } else if (b - a == 2 && by_sheet[a].second != by_sheet[a + 1].second) {
        edge_pairs.push_back({by_sheet[a].second, by_sheet[a + 1].second});
        edge_pairs.push_back({by_sheet[a + 1].second, by_sheet[a].second});
      } else {
        fits = false;  // a sheet touching itself here, or a face along the edge twice
      }
    }
    if (ends && fits) pairs.emplace(corners[i].edge, std::move(edge_pairs));
  }
  return pairs;
}

}  // namespace spheremap
