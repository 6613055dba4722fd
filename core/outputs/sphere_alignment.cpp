#include "core/outputs/sphere_alignment.h"

#include <Eigen/Dense>
#include <cmath>

namespace spheremap {
namespace {

double mean_cosine(std::span<const Vec3> positions, std::span<const Vec3> sphere,
                   const Vec3& centroid) {
  double sum = 0;
  size_t counted = 0;
  for (size_t v = 0; v < positions.size(); ++v) {
    const Vec3 d = positions[v] - centroid;
    const double length = norm(d);
    if (!(length > 0)) continue;
    sum += dot(d, sphere[v]) / length;
    ++counted;
  }
  return counted ? sum / static_cast<double>(counted) : 0;
}

}  // namespace

SphereAlignment align_sphere_to_surface(std::span<const Vec3> positions,
                                        std::span<const Vec3> sphere, const Vec3& centroid) {
  SphereAlignment out;
  out.mean_cosine_before = mean_cosine(positions, sphere, centroid);
  // H = sum of s d^T; with H = U S V^T the best R (R s ~ d) is V diag(1, 1, det(V U^T)) U^T.
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t v = 0; v < positions.size(); ++v) {
    const Vec3 d = positions[v] - centroid;
    const Eigen::Vector3d s(sphere[v].x, sphere[v].y, sphere[v].z);
    h += s * Eigen::RowVector3d(d.x, d.y, d.z);
  }
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (h.allFinite() && h.norm() > 0) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
    correction(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
    r = svd.matrixV() * correction * svd.matrixU().transpose();
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.rotation[i][j] = r(i, j);
  out.sphere.reserve(sphere.size());
  for (const Vec3& s : sphere) {
    const Eigen::Vector3d turned = r * Eigen::Vector3d(s.x, s.y, s.z);
    // Renormalised: the rotation's rounding must not move a point off the unit sphere.
    const double length = turned.norm();
    out.sphere.push_back(Vec3{turned.x(), turned.y(), turned.z()} * (1 / length));
  }
  out.mean_cosine_after = mean_cosine(positions, out.sphere, centroid);
  return out;
}

}  // namespace spheremap
