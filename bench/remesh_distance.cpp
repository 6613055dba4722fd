// remesh_distance: the bench's own yardstick of how close an output is to the ORIGINAL
// asset (Reach II's "Done when": a remesh within 2% of the original's diagonal). Reads
// both files with core/io's reader (as the CLI does; a GLB's whole scene) and measures
// with core/mesh/surface_distance against the original's triangles (non-finite corners
// skipped, and collapsed ones: two corners at one point make a segment or a point, which
// draws nothing and which the service's cleaning drops too), each direction separately.
//
//   remesh_distance ORIGINAL OUTPUT.glb
//
// Prints one JSON line: hausdorff and rms (two-sided), original_to_output and
// output_to_original (largest distance one way), their RMS, all relative to the
// original's bounding-box diagonal; and both triangle counts; the diagonal itself and the
// output vertex farthest from the original (where output_to_original's loss is, to tell a
// hole cap from a sampling loss). Exit 2 on unreadable input.
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/mesh/surface_distance.h"

namespace {

using namespace spheremap;

// The mesh's triangles (fanned polygons) whose corners are finite and at three points
// (magnum's nonindexed PLY test file has one triangle beside two segments and a point:
// measured to the segments, its remesh of the triangle stood 22.5% off).
std::vector<Triangle> drawn_triangles(const PolygonMesh& mesh) {
  std::vector<Triangle> out;
  for (const Triangle& t : fan_triangulate(mesh).triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    if (is_finite(a) && is_finite(b) && is_finite(c) && !(a == b) && !(b == c) && !(c == a))
      out.push_back(t);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: remesh_distance ORIGINAL OUTPUT.glb\n");
    return 2;
  }
  try {
    const PolygonMesh original = read_mesh_file(argv[1]);
    const PolygonMesh output = read_mesh_file(argv[2]);
    const std::vector<Triangle> a = drawn_triangles(original), b = drawn_triangles(output);
    const SurfaceDistance d = surface_distance(original.positions, a, output.positions, b, 1);
    // The output's vertex farthest from the original (vertices only: a locator, not a figure).
    const PointDistances far = point_distances(original.positions, a, output.positions, 1);
    size_t farthest = 0;
    for (size_t i = 0; i < far.relative.size(); ++i)
      if (far.relative[i] > far.relative[farthest]) farthest = i;
    nlohmann::json where = nullptr;
    if (!far.relative.empty())
      where = {output.positions[farthest].x, output.positions[farthest].y,
               output.positions[farthest].z};
    const nlohmann::json line = {{"hausdorff", d.hausdorff},
                                 {"hausdorff_at_most", d.hausdorff_at_most},
                                 {"hausdorff_settled", d.hausdorff_settled},
                                 {"rms", d.rms},
                                 {"original_to_output", d.max_a_to_b},
                                 {"output_to_original", d.max_b_to_a},
                                 {"rms_original_to_output", d.rms_a_to_b},
                                 {"rms_output_to_original", d.rms_b_to_a},
                                 {"original_triangles", a.size()},
                                 {"output_triangles", b.size()},
                                 {"diagonal", d.diagonal},
                                 {"farthest_output_vertex", where}};
    std::printf("%s\n", line.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "remesh_distance: %s\n", e.what());
    return 2;
  }
}
