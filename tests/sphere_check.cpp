// sphere_check: an independent judge of a spherical map written as OBJ. It shares no
// code with the engine: it parses `v` and `f` lines itself and checks that every vertex
// is on the unit sphere, that no face is flipped against the majority orientation (a
// face's signed spherical area, which does not depend on how it is triangulated), and
// that the signed areas add up to 4 pi (a map covering the sphere twice adds up to 8 pi).
// It also reports, for information, the triangles flipped when polygons are fanned
// from their first corner (a non-convex spherical polygon). Exit 0 = bijective, 1 = not,
// 2 = bad file. Prints one JSON line.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

struct P {
  double x, y, z;
};

static double det(const P& a, const P& b, const P& c) {
  return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
         a.z * (b.x * c.y - b.y * c.x);
}
static double dotp(const P& a, const P& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: sphere_check MAPPED.obj\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "sphere_check: cannot open %s\n", argv[1]);
    return 2;
  }
  std::vector<P> v;
  std::vector<std::vector<long>> faces;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "v") {
      P p{};
      s >> p.x >> p.y >> p.z;
      v.push_back(p);
    } else if (key == "f") {
      std::vector<long> f;
      std::string corner;
      while (s >> corner) f.push_back(std::stol(corner.substr(0, corner.find('/'))) - 1);
      faces.push_back(f);
    }
  }
  // Only vertices a face uses must be on the sphere (an unused one may sit anywhere).
  std::vector<char> used(v.size(), 0);
  for (const auto& f : faces)
    for (long id : f)
      if (id >= 0 && id < static_cast<long>(v.size())) used[static_cast<size_t>(id)] = 1;
  double max_radius_error = 0;
  for (size_t i = 0; i < v.size(); ++i)
    if (used[i])
      max_radius_error = std::fmax(max_radius_error, std::fabs(std::sqrt(dotp(v[i], v[i])) - 1));
  long positive = 0, negative = 0, fan_positive = 0, fan_negative = 0, triangles = 0;
  double area = 0;
  for (const auto& f : faces) {
    double face_area = 0;
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      for (long id : {f[0], f[k], f[k + 1]})
        if (id < 0 || id >= static_cast<long>(v.size())) {
          std::fprintf(stderr, "sphere_check: index out of range\n");
          return 2;
        }
      const P &a = v[f[0]], &b = v[f[k]], &c = v[f[k + 1]];
      const double d = det(a, b, c);
      (d > 0 ? fan_positive : fan_negative) += 1;
      face_area += 2 * std::atan2(d, 1 + dotp(a, b) + dotp(b, c) + dotp(c, a));
      ++triangles;
    }
    // A triangle's sign is its determinant's; zero counts against (not a bijection).
    const bool face_positive = f.size() == 3 ? det(v[f[0]], v[f[1]], v[f[2]]) > 0 : face_area > 0;
    (face_positive ? positive : negative) += 1;
    area += face_area;
  }
  const long flipped = positive < negative ? positive : negative;
  const long fan_flipped = fan_positive < fan_negative ? fan_positive : fan_negative;
  const bool bijective = triangles > 0 && flipped == 0 && max_radius_error < 1e-9 &&
                         std::fabs(std::fabs(area) - 4 * M_PI) < 1e-6;
  std::printf(
      "{\"faces\": %zu, \"triangles\": %ld, \"flipped_faces\": %ld, "
      "\"first_corner_fan_flips\": %ld, \"area_sum\": %.12f, \"max_radius_error\": %.3g, "
      "\"bijective\": %s}\n",
      faces.size(), triangles, flipped, fan_flipped, area, max_radius_error,
      bijective ? "true" : "false");
  return bijective ? 0 : 1;
}
