#include "tests/thin_plates.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

namespace spheremap::testing {
namespace {

using Point = std::array<double, 2>;

double cross(const Point& o, const Point& a, const Point& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// p strictly inside or on the boundary of the counter-clockwise triangle (a, b, c).
bool in_triangle(const Point& p, const Point& a, const Point& b, const Point& c) {
  return cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0;
}

// Ear clipping that walks round the outline and clips each ear it meets (no search for
// the best ear): what a simple exporter does, and it leaves long slivers.
std::vector<std::array<uint32_t, 3>> ear_clip(std::span<const Point> outline) {
  std::vector<uint32_t> left(outline.size());
  std::iota(left.begin(), left.end(), 0u);
  std::vector<std::array<uint32_t, 3>> out;
  size_t i = 0, misses = 0;
  while (left.size() > 3) {
    if (misses > left.size()) throw std::runtime_error("ear_clip: no ear (outline not simple)");
    const size_t n = left.size();
    const uint32_t a = left[(i + n - 1) % n], b = left[i % n], c = left[(i + 1) % n];
    bool ear = cross(outline[a], outline[b], outline[c]) > 0;
    for (size_t k = 0; ear && k < n; ++k) {
      const uint32_t p = left[k];
      if (p != a && p != b && p != c && in_triangle(outline[p], outline[a], outline[b], outline[c]))
        ear = false;
    }
    if (!ear) {
      i = (i + 1) % n, ++misses;
      continue;
    }
    out.push_back({a, b, c});
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(i % n));
    i = i % left.size();
    misses = 0;
  }
  out.push_back({left[0], left[1], left[2]});
  return out;
}

std::vector<std::array<uint32_t, 3>> fan(size_t n) {
  std::vector<std::array<uint32_t, 3>> out;
  for (uint32_t k = 1; k + 1 < n; ++k) out.push_back({0, k, k + 1});
  return out;
}

}  // namespace

PolygonMesh thin_plate(std::span<const Point> outline, double thickness, CapTriangulation caps) {
  PolygonMesh m;
  const auto n = static_cast<uint32_t>(outline.size());
  for (double z : {-thickness / 2, thickness / 2})
    for (const auto& [x, y] : outline) m.positions.push_back({x, y, z});
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    const uint32_t lower[3] = {i, j, n + j}, upper[3] = {i, n + j, n + i};
    m.add_face(lower);
    m.add_face(upper);
  }
  for (const auto& [a, b, c] : caps == CapTriangulation::kFan ? fan(n) : ear_clip(outline)) {
    const uint32_t bottom[3] = {a, c, b}, top[3] = {n + a, n + b, n + c};
    m.add_face(bottom);
    m.add_face(top);
  }
  return m;
}

std::vector<Point> circle_outline(int points) {
  std::vector<Point> out;
  for (int k = 0; k < points; ++k) {
    const double a = 2 * M_PI * k / points;
    out.push_back({std::cos(a), std::sin(a)});
  }
  return out;
}

std::vector<Point> rounded_rectangle_outline(int points_per_corner) {
  // A bank card's proportions (85.6 x 54 mm, corner radius 3.2 mm), 2 units long.
  const double half_x = 1.0, half_y = 54.0 / 85.6, r = 2 * 3.2 / 85.6;
  const Point centres[4] = {{half_x - r, half_y - r},
                            {-half_x + r, half_y - r},
                            {-half_x + r, -half_y + r},
                            {half_x - r, -half_y + r}};
  std::vector<Point> out;
  for (int corner = 0; corner < 4; ++corner)
    for (int k = 0; k < points_per_corner; ++k) {
      const double a = M_PI / 2 * (corner + static_cast<double>(k) / (points_per_corner - 1));
      out.push_back({centres[corner][0] + r * std::cos(a), centres[corner][1] + r * std::sin(a)});
    }
  return out;
}

std::vector<Point> leaf_outline(int points) {
  // Pointed at both ends: the half-width grows like sin^1.5 from each tip.
  std::vector<Point> out;
  for (int k = 0; k < points; ++k) {
    const double t = 2 * M_PI * k / points, s = std::sin(t);
    out.push_back({std::cos(t), 0.45 * std::copysign(std::pow(std::abs(s), 1.5), s)});
  }
  return out;
}

std::vector<Point> heart_outline(int points) {
  // The classic heart curve, 2 units tall; counter-clockwise, notch at the top.
  std::vector<Point> out;
  for (int k = 0; k < points; ++k) {
    const double t = -2 * M_PI * k / points, s = std::sin(t);
    out.push_back(
        {16 * s * s * s / 17,
         (13 * std::cos(t) - 5 * std::cos(2 * t) - 2 * std::cos(3 * t) - std::cos(4 * t)) / 17});
  }
  return out;
}

std::vector<NamedMesh> thin_plates() {
  constexpr double kThickness = 2e-3;  // 1e-3 of the diameter (outlines are ~2 across)
  std::vector<NamedMesh> out;
  out.push_back(
      {"plate_coin", thin_plate(circle_outline(2048), kThickness, CapTriangulation::kFan)});
  out.push_back({"plate_card", thin_plate(rounded_rectangle_outline(64), kThickness,
                                          CapTriangulation::kEarClip)});
  out.push_back(
      {"plate_leaf", thin_plate(leaf_outline(1500), kThickness, CapTriangulation::kEarClip)});
  out.push_back(
      {"plate_heart", thin_plate(heart_outline(4285), kThickness, CapTriangulation::kEarClip)});
  return out;
}

}  // namespace spheremap::testing
