#include "core/map/part_copies.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace spheremap {
namespace {

Vec3 centroid(std::span<const Vec3> points) {
  Vec3 c;
  for (const Vec3& p : points) c += p;
  return c * (1.0 / static_cast<double>(points.size()));
}

}  // namespace

uint64_t faces_hash(const PolygonMesh& mesh, std::span<const Triangle> filled) {
  uint64_t h = 1469598103934665603ull;
  auto add = [&h](uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  add(mesh.vertex_count());
  for (uint32_t o : mesh.offsets) add(o);
  for (uint32_t v : mesh.indices) add(v);
  for (const Triangle& t : filled)
    for (uint32_t v : t) add(v);
  return h;
}

uint64_t shape_hash(std::span<const Vec3> positions) {
  if (positions.empty()) return 0;
  const Vec3 c = centroid(positions);
  double sum = 0;
  for (const Vec3& p : positions) sum += squared_norm(p - c);
  const double rms = std::sqrt(sum / static_cast<double>(positions.size()));
  if (!(rms > 0)) return 0;
  uint64_t h = 1469598103934665603ull;
  const size_t count = std::min<size_t>(positions.size(), 4);
  for (size_t i = 0; i < count; ++i) {
    const auto step = static_cast<uint64_t>(std::lround(norm(positions[i] - c) / rms * 64));
    h = (h ^ step) * 1099511628211ull;
  }
  return h;
}

bool same_faces(const PolygonMesh& a, std::span<const Triangle> a_filled, const PolygonMesh& b,
                std::span<const Triangle> b_filled) {
  return a.vertex_count() == b.vertex_count() && a.offsets == b.offsets && a.indices == b.indices &&
         std::equal(a_filled.begin(), a_filled.end(), b_filled.begin(), b_filled.end());
}

Vec3 rotate(const Rotation& r, const Vec3& v) {
  return {r[0] * v.x + r[1] * v.y + r[2] * v.z, r[3] * v.x + r[4] * v.y + r[5] * v.z,
          r[6] * v.x + r[7] * v.y + r[8] * v.z};
}

std::optional<Rotation> rotation_onto(std::span<const Vec3> from, std::span<const Vec3> to,
                                      double tolerance) {
  if (from.empty() || from.size() != to.size()) return std::nullopt;
  const Vec3 cf = centroid(from), ct = centroid(to);
  // Kabsch: the rotation that best turns `from` onto `to` is V U^T of the SVD of their
  // cross-covariance U S V^T; a negative determinant means only a mirror fits.
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  double from_squares = 0, to_squares = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    const Vec3 x = from[i] - cf, y = to[i] - ct;
    const Eigen::Vector3d ex(x.x, x.y, x.z), ey(y.x, y.y, y.z);
    h += ex * ey.transpose();
    from_squares += squared_norm(x);
    to_squares += squared_norm(y);
  }
  if (!(from_squares > 0) || !(to_squares > 0) || !std::isfinite(from_squares + to_squares))
    return std::nullopt;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d r = svd.matrixV() * svd.matrixU().transpose();
  if (!(r.determinant() > 0)) return std::nullopt;
  const Rotation rotation = {r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1),
                             r(1, 2), r(2, 0), r(2, 1), r(2, 2)};
  const double scale = std::sqrt(to_squares / from_squares);
  const double n = static_cast<double>(from.size());
  const double limit = tolerance * std::sqrt(to_squares / n);
  for (size_t i = 0; i < from.size(); ++i)
    if (!(norm(rotate(rotation, from[i] - cf) * scale - (to[i] - ct)) <= limit))
      return std::nullopt;
  return rotation;
}

}  // namespace spheremap
