// speed_bench: the yardstick of issue 30 ("Speed at scale"). The work every collapse
// hierarchy must do anyway is a QEM simplification of the whole mesh: meshoptimizer's
// meshopt_simplify on the same welded triangles, vertices in meshopt_spatialSortRemap
// order, down to 4 triangles, one thread, in this process. Against it, our collapse
// hierarchy built as the map builds it (hierarchy_bench's setup). The whole map's time is
// measured around the CLI process by bench/speed/run.sh, which calls this for the yardstick.
//
//   speed_bench [--repeat N] MESH...
//     one JSON line per mesh: triangles, meshopt_seconds and hierarchy_seconds (min of N,
//     default 5, each with its median), the triangles meshopt_simplify reached.
//   speed_bench --subdivide K IN OUT.ply
//     IN's welded triangles split 1-to-4 K times (flat: new vertices at edge midpoints),
//     written as binary little-endian PLY: the 17M-triangle mesh of issue 30 is igea with K=3.
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/map/hierarchy.h"
#include "core/map/pipeline.h"
#include "core/mesh/spatial_order.h"
#include "core/prepare/prepare_mesh.h"

namespace {

using namespace spheremap;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The welded mesh's triangles (polygons fanned), as one index list.
std::vector<uint32_t> triangles_of(const PolygonMesh& mesh) {
  std::vector<uint32_t> indices;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 1; k + 1 < face.size(); ++k)
      indices.insert(indices.end(), {face[0], face[k], face[k + 1]});
  }
  return indices;
}

struct Timing {
  double min = 0, median = 0;
};

template <typename Run>
Timing time_runs(int repeat, Run&& run) {
  std::vector<double> seconds;
  for (int r = 0; r < repeat; ++r) {
    const auto start = Clock::now();
    run();
    seconds.push_back(seconds_since(start));
  }
  std::sort(seconds.begin(), seconds.end());
  return {seconds.front(), seconds[seconds.size() / 2]};
}

int measure(const std::string& path, int repeat) {
  const PreparedMesh prepared = prepare_mesh(read_mesh_file(path), {});
  const PolygonMesh& welded = prepared.welded.mesh;

  // meshopt_simplify's input: float positions in spatial order, the triangles renumbered.
  const size_t vertex_count = welded.vertex_count();
  std::vector<float> positions(3 * vertex_count);
  for (size_t v = 0; v < vertex_count; ++v) {
    positions[3 * v] = static_cast<float>(welded.positions[v].x);
    positions[3 * v + 1] = static_cast<float>(welded.positions[v].y);
    positions[3 * v + 2] = static_cast<float>(welded.positions[v].z);
  }
  std::vector<uint32_t> indices = triangles_of(welded);
  std::vector<unsigned int> remap(vertex_count);
  meshopt_spatialSortRemap(remap.data(), positions.data(), vertex_count, 3 * sizeof(float));
  meshopt_remapVertexBuffer(positions.data(), positions.data(), vertex_count, 3 * sizeof(float),
                            remap.data());
  meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
  std::vector<uint32_t> simplified(indices.size());
  size_t reached = 0;
  const Timing meshopt = time_runs(repeat, [&] {
    reached = meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(),
                               vertex_count, 3 * sizeof(float), 12, 1e30f, 0, nullptr);
  });

  // Our hierarchy, from what the map's first attempt sees (hierarchy_bench's setup).
  MappingInput input = mapping_input(welded, morton_order(welded.positions));
  const Timing hierarchy = time_runs(repeat, [&] {
    const CollapseHierarchy h =
        build_hierarchy(input.mesh.positions, input.oriented.triangles, MapOptions{}.level_growth);
    if (h.level_sizes.empty()) std::abort();  // keeps the build from being optimized away
  });

  const nlohmann::json row = {{"mesh", path.substr(path.find_last_of('/') + 1)},
                              {"triangles", indices.size() / 3},
                              {"meshopt_seconds", meshopt.min},
                              {"meshopt_seconds_median", meshopt.median},
                              {"meshopt_reached_triangles", reached / 3},
                              {"hierarchy_seconds", hierarchy.min},
                              {"hierarchy_seconds_median", hierarchy.median}};
  std::printf("%s\n", row.dump().c_str());
  std::fflush(stdout);
  return 0;
}

// Splits every triangle into 4 through its edge midpoints, each midpoint made once.
void subdivide_once(std::vector<float>& positions, std::vector<uint32_t>& indices) {
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
  auto middle = [&](uint32_t a, uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [at, added] = midpoint.try_emplace({key.first, key.second}, 0);
    if (added) {
      at->second = static_cast<uint32_t>(positions.size() / 3);
      for (int c = 0; c < 3; ++c)
        positions.push_back(0.5f * (positions[3 * a + c] + positions[3 * b + c]));
    }
    return at->second;
  };
  std::vector<uint32_t> out;
  out.reserve(4 * indices.size());
  for (size_t t = 0; t < indices.size(); t += 3) {
    const uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
    const uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
    out.insert(out.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  indices = std::move(out);
}

int subdivide(const std::string& in, int times, const std::string& out_path) {
  const PreparedMesh prepared = prepare_mesh(read_mesh_file(in), {});
  const PolygonMesh& welded = prepared.welded.mesh;
  std::vector<float> positions;
  for (const Vec3& p : welded.positions)
    positions.insert(positions.end(),
                     {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  std::vector<uint32_t> indices = triangles_of(welded);
  for (int k = 0; k < times; ++k) subdivide_once(positions, indices);
  FILE* out = std::fopen(out_path.c_str(), "wb");
  if (!out) {
    std::perror(out_path.c_str());
    return 1;
  }
  std::fprintf(out,
               "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty float x\n"
               "property float y\nproperty float z\nelement face %zu\n"
               "property list uchar uint vertex_indices\nend_header\n",
               positions.size() / 3, indices.size() / 3);
  std::fwrite(positions.data(), sizeof(float), positions.size(), out);
  for (size_t t = 0; t < indices.size(); t += 3) {
    const unsigned char three = 3;
    std::fwrite(&three, 1, 1, out);
    std::fwrite(&indices[t], sizeof(uint32_t), 3, out);
  }
  const bool written = std::fclose(out) == 0;
  std::printf("%s: %zu vertices, %zu triangles\n", out_path.c_str(), positions.size() / 3,
              indices.size() / 3);
  return written ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 5;
  std::vector<std::string> meshes;
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--repeat") && k + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++k]));
    } else if (!std::strcmp(argv[k], "--subdivide") && k + 3 < argc) {
      return subdivide(argv[k + 2], std::atoi(argv[k + 1]), argv[k + 3]);
    } else {
      meshes.push_back(argv[k]);
    }
  }
  if (meshes.empty()) {
    std::fprintf(stderr,
                 "usage: speed_bench [--repeat N] MESH...\n"
                 "       speed_bench --subdivide K IN OUT.ply\n");
    return 2;
  }
  for (const std::string& path : meshes)
    if (measure(path, repeat) != 0) return 1;
  return 0;
}
