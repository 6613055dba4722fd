#include "core/prepare/far_disc_fills.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "core/mesh/triangle_tree.h"
#include "core/mesh/union_find.h"
#include "core/prepare/hole_filling.h"

namespace spheremap {
namespace {
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
}  // namespace

FarDiscFills::FarDiscFills(const PolygonMesh& mesh, double max_distance)
    : mesh_(mesh), max_distance_(max_distance), own_faces_(mesh.face_count()) {}

void FarDiscFills::count_parts() const {
  const PolygonMesh& mesh = mesh_;
  counted_ = true;
  UnionFind sets(mesh.vertex_count());
  for (size_t f = 0; f < own_faces_; ++f)
    for (uint32_t v : mesh.face(f)) sets.unite(mesh.face(f)[0], v);
  // Parts numbered by their first face; vertices in no face belong to none.
  std::unordered_map<uint32_t, uint32_t> part_of_root;
  part_of_.assign(mesh.vertex_count(), kNone);
  std::vector<uint32_t> face_part(own_faces_);
  for (size_t f = 0; f < own_faces_; ++f) {
    const uint32_t root = sets.find(mesh.face(f)[0]);
    const auto [it, added] = part_of_root.emplace(root, static_cast<uint32_t>(euler_.size()));
    if (added) euler_.push_back(0), boundary_edges_.push_back(0);
    face_part[f] = it->second;
    ++euler_[it->second];  // + F
    for (uint32_t v : mesh.face(f))
      if (part_of_[v] == kNone) part_of_[v] = it->second, ++euler_[it->second];  // + V
  }
  // Edges: - E, and those with one face are boundary edges.
  std::unordered_map<uint64_t, uint32_t> faces_at;
  for (size_t f = 0; f < own_faces_; ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      ++faces_at[undirected_edge_key(face[k], face[(k + 1) % face.size()])];
  }
  for (const auto& [key, count] : faces_at) {
    const uint32_t part = part_of_[static_cast<uint32_t>(key)];
    --euler_[part];
    if (count == 1) ++boundary_edges_[part];
  }
  first_face_.assign(euler_.size() + 1, 0);
  for (uint32_t part : face_part) ++first_face_[part + 1];
  for (size_t p = 0; p < euler_.size(); ++p) first_face_[p + 1] += first_face_[p];
  faces_.resize(own_faces_);
  std::vector<uint32_t> next(first_face_.begin(), first_face_.end() - 1);
  for (size_t f = 0; f < own_faces_; ++f) faces_[next[face_part[f]]++] = static_cast<uint32_t>(f);
}

bool FarDiscFills::operator()(std::span<const uint32_t> loop,
                              std::span<const Triangle> fill) const {
  if (!counted_) count_parts();
  if (loop.empty() || loop[0] >= part_of_.size() || part_of_[loop[0]] == kNone) return false;
  const uint32_t part = part_of_[loop[0]];
  if (euler_[part] != 1 || boundary_edges_[part] != loop.size()) return false;
  std::vector<Triangle> triangles;
  Vec3 low = mesh_.positions[loop[0]], high = low;
  for (uint32_t k = first_face_[part]; k < first_face_[part + 1]; ++k) {
    const auto face = mesh_.face(faces_[k]);
    for (uint32_t v : face) {
      const Vec3& p = mesh_.positions[v];
      low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
      high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
    }
    for (size_t i = 1; i + 1 < face.size(); ++i)
      triangles.push_back({face[0], face[i], face[i + 1]});
  }
  const TriangleTree own(mesh_.positions, triangles);
  return farthest_from(own, mesh_.positions, fill) > max_distance_ * norm(high - low);
}

}  // namespace spheremap
