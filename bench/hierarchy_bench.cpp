// hierarchy_bench: the collapse hierarchy alone, as the map builds it (welded mesh in
// Morton order, centred and scaled, oriented triangles in canonical order),
// timed over repeated builds, with a hash of everything the map reads from it, so a faster
// build can be shown to be the same one.
//
//   hierarchy_bench [--repeat N] [--growth G] [--file-order] MESH...
//
// --file-order: the triangles in the file's order (as the map took them before
// canonical_triangles), to measure what the order costs.
//
// Prints one JSON line per mesh: vertices, rounds, levels, seconds (min and median of N
// builds, default 7), and hash (FNV-1a over new_to_old, level sizes, level triangles,
// collapse targets and rings).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/map/hierarchy.h"
#include "core/map/pipeline.h"
#include "core/mesh/spatial_order.h"

namespace {

using namespace spheremap;

struct Fnv1a {
  uint64_t h = 1469598103934665603ull;
  void add(std::span<const uint32_t> words) {
    for (uint32_t w : words)
      for (int b = 0; b < 4; ++b) h = (h ^ ((w >> (8 * b)) & 0xff)) * 1099511628211ull;
  }
};

uint64_t hash_of(const CollapseHierarchy& h) {
  Fnv1a f;
  f.add(h.new_to_old);
  f.add(h.level_sizes);
  for (const auto& level : h.level_triangles) f.add({level.data()->data(), 3 * level.size()});
  f.add(h.collapse_target);
  f.add(h.ring_offsets);
  f.add(h.rings);
  return f.h;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 7;
  double growth = 2.0;  // the optimized map's levels (MapOptions::level_growth)
  bool file_order = false;
  std::vector<std::string> meshes;
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--repeat") && k + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--file-order"))
      file_order = true;
    else if (!std::strcmp(argv[k], "--growth") && k + 1 < argc)
      growth = std::atof(argv[++k]);
    else
      meshes.push_back(argv[k]);
  }
  if (meshes.empty()) {
    std::fprintf(stderr,
                 "usage: hierarchy_bench [--repeat N] [--growth G] [--file-order] MESH...\n");
    return 2;
  }
  for (const std::string& path : meshes) {
    const PreparedMesh prepared = prepare_mesh(read_mesh_file(path), {});
    const PolygonMesh& welded = prepared.welded.mesh;
    // What the map's first attempt sees (map_to_sphere): Morton order, unit ball, canonical.
    MappingInput input = mapping_input(welded, morton_order(welded.positions));
    const PolygonMesh& mesh = input.mesh;
    OrientedTriangles& oriented = input.oriented;
    if (file_order) oriented = oriented_triangles(mesh);
    std::vector<double> seconds;
    uint64_t hash = 0;
    CollapseHierarchy h;
    for (int r = 0; r < repeat; ++r) {
      const auto start = std::chrono::steady_clock::now();
      h = build_hierarchy(mesh.positions, oriented.triangles, growth);
      seconds.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      const uint64_t this_hash = hash_of(h);
      if (r > 0 && this_hash != hash) {
        std::fprintf(stderr, "%s: builds differ between runs\n", path.c_str());
        return 1;
      }
      hash = this_hash;
    }
    std::sort(seconds.begin(), seconds.end());
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
    nlohmann::json row = {{"mesh", path.substr(path.find_last_of('/') + 1)},
                          {"vertices", mesh.vertex_count()},
                          {"rounds", h.rounds},
                          {"levels", h.level_sizes.size()},
                          {"seconds_min", seconds.front()},
                          {"seconds_median", seconds[seconds.size() / 2]},
                          {"hash", hex}};
    std::printf("%s\n", row.dump().c_str());
  }
  return 0;
}
