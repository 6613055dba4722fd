#include "core/prepare/far_hole_fills.h"

#include <limits>
#include <numeric>

#include "core/mesh/topology.h"
#include "core/prepare/connected_parts.h"
#include "core/prepare/open_part_cuts.h"  // can_become_disc

namespace spheremap {
namespace {
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// An open part with handles: its only failure a boundary, of genus > 0 (orientable).
// Under auto hole_cones.h cones its holes for the handle search, its handles are cut and
// it becomes an open sphere, cut into a disc: a far hole is left for its back as an open
// sphere's is (a bathymetry block with a tunnel: its 3.9%-of-the-area hole filled stood
// 6.5% of the diagonal off).
bool is_open_with_handles(const TopologyReport& topology) {
  const std::vector<ValidationFailure> failures = mapping_failures(topology);
  const long long twice_genus =
      2 - topology.euler_characteristic - static_cast<long long>(topology.boundary_loops);
  return failures.size() == 1 && failures.front().check == "boundary" && twice_genus >= 2 &&
         twice_genus % 2 == 0;
}

}  // namespace

FarHoleFills::FarHoleFills(const PolygonMesh& mesh, double max_distance)
    : mesh_(mesh), max_distance_(max_distance), own_faces_(mesh.face_count()) {}

void FarHoleFills::find_parts() const {
  found_ = true;
  // The faces the mesh had when this was made (fills appended since are not the parts').
  PolygonMesh own;
  own.positions = mesh_.positions;
  own.offsets.assign(mesh_.offsets.begin(), mesh_.offsets.begin() + own_faces_ + 1);
  own.indices.assign(mesh_.indices.begin(), mesh_.indices.begin() + own.offsets.back());
  part_of_.assign(own.vertex_count(), kNone);
  for (MeshPart& part : connected_parts(own)) {
    const TopologyReport topology = analyze_topology(part.mesh);
    if (!can_become_disc(topology, part.mesh.indices.size()) && !is_open_with_handles(topology))
      continue;
    for (uint32_t v : part.vertex) part_of_[v] = static_cast<uint32_t>(parts_.size());
    parts_.push_back(std::move(part.mesh));
  }
  trees_.resize(parts_.size());
  diagonals_.assign(parts_.size(), 0);
}

bool FarHoleFills::operator()(std::span<const uint32_t> loop,
                              std::span<const Triangle> fill) const {
  if (!found_) find_parts();
  if (loop.empty() || loop[0] >= part_of_.size() || part_of_[loop[0]] == kNone) return false;
  const uint32_t k = part_of_[loop[0]];
  if (!trees_[k]) {
    const PolygonMesh& part = parts_[k];
    AxisBox box;
    for (const Vec3& p : part.positions) box.add(p);
    diagonals_[k] = norm(box.hi - box.lo);
    std::vector<uint32_t> faces(part.face_count());
    std::iota(faces.begin(), faces.end(), 0u);
    trees_[k].emplace(polygon_tree(part, faces));
  }
  return farthest_from(*trees_[k], mesh_.positions, fill) > max_distance_ * diagonals_[k];
}

}  // namespace spheremap
