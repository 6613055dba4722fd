// envelope_bench: issue 29 item 7. Our dense envelope grid against OpenVDB's narrow band at
// the same voxel size and offset as build_envelope's defaults (h = diagonal / resolution,
// d = 1.5 h), on one mesh read as the CLI reads it. One variant per process, so that the
// process's peak RSS is the variant's: run it once per variant.
//
//   envelope_bench [--variant V] [--resolution R] [--repeat N] [--threads T] [--write OUT.obj]
//                  MESH
//     V: grid      our band_voxels then fill_enclosed (envelope_grid.h)
//        envelope  the whole build_envelope, and its stages timed once apart
//        vdb-udf   openvdb::tools::meshToUnsignedDistanceField, half-width d / h voxels
//        vdb-sdf   openvdb::tools::meshToLevelSet, half-width d / h + 1 voxels, then
//                  sdfInteriorMask at d (the band plus OpenVDB's own interior fill)
//     T: OpenVDB's TBB threads, and the envelope's (its distance for the metrics) (default
//        1: our grid runs on one thread).
//     OUT.obj: the envelope (variant envelope) as an OBJ, to map or look at on its own.
//     One JSON line: the grid, voxels touched, seconds (min and median of N, default 3),
//     the containers' bytes where known, the peak RSS after reading and at the end.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/io/obj.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/surface_distance.h"
#include "core/mesh/triangle_tree.h"
#include "core/prepare/envelope.h"
#include "core/prepare/envelope_check.h"
#include "core/prepare/envelope_fit.h"
#include "core/prepare/envelope_grid.h"
#include "core/prepare/envelope_plan.h"
#include "core/prepare/envelope_reduce.h"
#include "core/prepare/envelope_surface.h"
#include "core/prepare/envelope_topology.h"

#ifdef SPHEREMAP_WITH_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>
#endif

namespace {

using namespace spheremap;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The process's peak resident set so far (VmHWM), in bytes.
long long peak_rss() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atoll(line.c_str() + 6) * 1024;
  return -1;
}

// The input as build_envelope sees it: fanned triangles with finite corners, their box.
struct Input {
  PolygonMesh mesh;
  std::vector<Triangle> triangles;
  AxisBox box;
};

Input read_input(const std::string& path) {
  Input in{read_mesh_file(path), {}, {}};
  for (const Triangle& t : fan_triangulate(in.mesh).triangles) {
    const Vec3 &a = in.mesh.positions[t[0]], &b = in.mesh.positions[t[1]],
               &c = in.mesh.positions[t[2]];
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) continue;
    in.triangles.push_back(t);
    in.box.add(a), in.box.add(b), in.box.add(c);
  }
  return in;
}

// The 8x8x8 bricks (aligned at multiples of 8) holding at least one voxel set in `voxels`:
// what a sparse grid of our own would allocate for them.
size_t bricks_touched(const VoxelGrid& grid, const std::vector<uint8_t>& voxels) {
  const int bx = (grid.nx + 7) / 8, by = (grid.ny + 7) / 8, bz = (grid.nz + 7) / 8;
  std::vector<uint8_t> touched(size_t(bx) * by * bz, 0);
  for (int z = 0; z < grid.nz; ++z)
    for (int y = 0; y < grid.ny; ++y)
      for (int x = 0; x < grid.nx; ++x)
        if (voxels[grid.index(x, y, z)]) touched[(size_t(z / 8) * by + y / 8) * bx + x / 8] = 1;
  return size_t(std::count(touched.begin(), touched.end(), uint8_t{1}));
}

// The process's CPU seconds so far (all threads): on the loaded shared machine a steadier
// figure than the wall clock for work on one thread.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// FNV-1a over the envelope's positions' and faces' bytes: whether a change left the
// envelope bit-identical.
std::string envelope_hash(const PolygonMesh& mesh) {
  uint64_t h = 1469598103934665603ull;
  const auto add = [&](const void* data, size_t bytes) {
    for (size_t k = 0; k < bytes; ++k)
      h = (h ^ static_cast<const uint8_t*>(data)[k]) * 1099511628211ull;
  };
  add(mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto c = mesh.face(f);
    for (const uint32_t v : c) add(&v, sizeof v);
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

struct Timing {
  double min = 0, median = 0, cpu_min = 0;
};

// Runs `run` `repeat` times; the min and median wall seconds, the min CPU seconds.
template <typename Run>
Timing time_runs(int repeat, Run&& run) {
  std::vector<double> seconds;
  double cpu_min = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto start = Clock::now();
    const double cpu = cpu_seconds();
    run();
    cpu_min = std::min(cpu_min, cpu_seconds() - cpu);
    seconds.push_back(seconds_since(start));
  }
  std::sort(seconds.begin(), seconds.end());
  return {seconds.front(), seconds[seconds.size() / 2], cpu_min};
}

// build_envelope's stages one after the other (as envelope.cpp calls them), each timed.
Json envelope_stages(const Input& in, const VoxelGrid& grid, double d, double fit_distance,
                     int threads) {
  StopCheck stop(nullptr);
  Json stages;
  auto t = Clock::now();
  double cpu = cpu_seconds();
  const auto lap = [&](const char* name) {
    stages[name] = {seconds_since(t), cpu_seconds() - cpu};  // wall, CPU
    t = Clock::now();
    cpu = cpu_seconds();
  };
  std::vector<uint8_t> solid = band_voxels(grid, in.mesh.positions, in.triangles, d, stop);
  lap("band");
  fill_enclosed(grid, solid, stop);
  lap("fill");
  BallGrowth ball = grow_ball_inside(grid, solid, stop);
  lap("grow_inside");
  // Always grown here, so that its cost shows: build_envelope skips it when the cut changed
  // nothing (the solid is a ball already; "outside_skipped").
  BallGrowth filled = shrink_ball_outside(grid, solid, stop);
  stages["outside_skipped"] = ball.voxels_changed == 0;
  lap("grow_outside");
  if (filled.voxels_changed < ball.voxels_changed) std::swap(ball, filled);
  filled = {};
  solid = {};
  PolygonMesh voxels = voxel_surface(grid, ball.ball, stop);
  ball = {};
  lap("voxel_surface");
  (void)envelope_failures(voxels);
  lap("check");
  smooth_surface(voxels, 6, stop);
  lap("smooth");
  const TriangleTree original(in.mesh.positions, in.triangles);
  lap("tree");
  PolygonMesh mesh =
      reduce_surface(voxels, std::clamp<size_t>(in.triangles.size(), 20000, 200000), stop);
  lap("reduce");
  (void)envelope_failures(mesh);
  fit_to_offset(mesh, original, fit_distance, 5, threads, stop);
  (void)envelope_failures(mesh);
  lap("fit");
  std::vector<Triangle> triangles(mesh.face_count());
  for (size_t f = 0; f < triangles.size(); ++f) {
    const auto c = mesh.face(f);
    triangles[f] = {c[0], c[1], c[2]};
  }
  (void)surface_distance(in.mesh.positions, in.triangles, mesh.positions, triangles, threads,
                         nullptr, DistanceSamples::kVertices);
  lap("distance");
  return stages;
}

#ifdef SPHEREMAP_WITH_OPENVDB
// One OpenVDB run: the grid's voxel (i, j, k) centred where ours is.
Json vdb_run(const Input& in, const VoxelGrid& grid, double d, bool sdf) {
  const auto xform = openvdb::math::Transform::createLinearTransform(grid.h);
  xform->postTranslate(openvdb::Vec3d(grid.origin.x + 0.5 * grid.h, grid.origin.y + 0.5 * grid.h,
                                      grid.origin.z + 0.5 * grid.h));
  std::vector<openvdb::Vec3s> points(in.mesh.positions.size());
  for (size_t v = 0; v < points.size(); ++v) {
    const Vec3& p = in.mesh.positions[v];
    points[v] = openvdb::Vec3s(float(p.x), float(p.y), float(p.z));
  }
  std::vector<openvdb::Vec3I> triangles(in.triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    triangles[t] = openvdb::Vec3I(in.triangles[t][0], in.triangles[t][1], in.triangles[t][2]);
  const std::vector<openvdb::Vec4I> quads;
  const float width = float(d / grid.h);
  Json out;
  if (!sdf) {
    const openvdb::FloatGrid::Ptr udf =
        openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles,
                                                                        quads, width);
    size_t band = 0;
    for (auto v = udf->cbeginValueOn(); v; ++v) band += *v <= float(d);
    out["active_voxels"] = udf->activeVoxelCount();
    out["band_voxels"] = band;
    out["container_bytes"] = udf->memUsage();
    out["leaves"] = udf->tree().leafCount();
    return out;
  }
  const openvdb::FloatGrid::Ptr sdf_grid =
      openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, width + 1);
  const openvdb::BoolGrid::Ptr solid = openvdb::tools::sdfInteriorMask(*sdf_grid, float(d));
  out["active_voxels"] = sdf_grid->activeVoxelCount();
  out["solid_voxels"] = solid->activeVoxelCount();
  out["container_bytes"] = sdf_grid->memUsage() + solid->memUsage();
  out["leaves"] = sdf_grid->tree().leafCount();
  return out;
}
#endif

int run(const std::string& path, const std::string& variant, double resolution, int repeat,
        const std::string& write, int threads) {
  const Input in = read_input(path);
  const long long rss_read = peak_rss();
  const double diagonal = norm(in.box.hi - in.box.lo);
  EnvelopeOptions options;
  options.resolution = resolution;
  options.threads = threads;
  const double h = diagonal / resolution, d = options.offset_voxels * h;
  const VoxelGrid grid = layout_grid(in.box.lo, in.box.hi, h, d, options.max_voxels);

  Json out;
  out["mesh"] = path;
  out["variant"] = variant;
  out["triangles"] = in.triangles.size();
  out["resolution"] = resolution;
  out["voxel_size"] = h;
  out["offset"] = d;
  out["grid"] = {grid.nx, grid.ny, grid.nz};
  out["grid_voxels"] = grid.size();
  StopCheck stop(nullptr);
  Timing seconds;
  if (variant == "grid") {
    std::vector<uint8_t> solid;
    double band_min = 1e300, fill_min = 1e300;
    seconds = time_runs(repeat, [&] {
      solid = {};
      auto start = Clock::now();
      solid = band_voxels(grid, in.mesh.positions, in.triangles, d, stop);
      band_min = std::min(band_min, seconds_since(start));
      start = Clock::now();
      fill_enclosed(grid, solid, stop);
      fill_min = std::min(fill_min, seconds_since(start));
    });
    out["solid_voxels"] = size_t(std::count(solid.begin(), solid.end(), uint8_t{1}));
    out["solid_bricks"] = bricks_touched(grid, solid);
    solid = band_voxels(grid, in.mesh.positions, in.triangles, d, stop);  // again, to count
    out["band_voxels"] = size_t(std::count(solid.begin(), solid.end(), uint8_t{1}));
    out["band_bricks"] = bricks_touched(grid, solid);
    out["band_seconds_min"] = band_min;
    out["fill_seconds_min"] = fill_min;
    out["container_bytes"] = grid.size();  // the solid's byte per voxel (the fill adds one)
  } else if (variant == "envelope") {
    Envelope envelope;
    seconds = time_runs(repeat, [&] {
      envelope = {};
      envelope = build_envelope(in.mesh, options);
    });
    out["solid_voxels"] = envelope.report.solid_voxels;
    out["faces"] = envelope.report.faces;
    out["hausdorff"] = envelope.report.hausdorff;
    out["rms"] = envelope.report.rms;
    out["envelope_hash"] = envelope_hash(envelope.mesh);
    if (!write.empty()) std::ofstream(write, std::ios::binary) << format_obj(envelope.mesh);
    envelope = {};
    // The stages, min of the repeats (wall and CPU each): on a shared machine one run's
    // stage times vary by a third.
    const double fit_distance = plan_envelope(in.mesh, options).fit_distance;
    Json stages;
    for (int r = 0; r < repeat; ++r) {
      const Json once = envelope_stages(in, grid, d, fit_distance, threads);
      for (const auto& [name, value] : once.items())
        if (!value.is_array() || !stages.contains(name))
          stages[name] = value;
        else
          for (int k = 0; k < 2; ++k)
            stages[name][k] = std::min(stages[name][k].get<double>(), value[k].get<double>());
    }
    out["stages_seconds"] = stages;
#ifdef SPHEREMAP_WITH_OPENVDB
  } else if (variant == "vdb-udf" || variant == "vdb-sdf") {
    openvdb::initialize();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    out["threads"] = threads;
    seconds = time_runs(repeat, [&] { out.update(vdb_run(in, grid, d, variant == "vdb-sdf")); });
#endif
  } else {
    std::fprintf(stderr, "unknown variant %s (OpenVDB variants need a build with OpenVDB)\n",
                 variant.c_str());
    return 2;
  }
  out["seconds_min"] = seconds.min;
  out["seconds_median"] = seconds.median;
  out["cpu_seconds_min"] = seconds.cpu_min;
  out["repeat"] = repeat;
  out["peak_rss_after_read"] = rss_read;
  out["peak_rss"] = peak_rss();
  std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string variant = "grid", mesh, write;
  double resolution = 256;
  int repeat = 3, threads = 1;
  for (int k = 1; k < argc; ++k) {
    const bool value = k + 1 < argc;
    if (!std::strcmp(argv[k], "--variant") && value)
      variant = argv[++k];
    else if (!std::strcmp(argv[k], "--resolution") && value)
      resolution = std::atof(argv[++k]);
    else if (!std::strcmp(argv[k], "--repeat") && value)
      repeat = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--threads") && value)
      threads = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--write") && value)
      write = argv[++k];
    else if (argv[k][0] != '-' && mesh.empty())
      mesh = argv[k];
    else
      mesh.clear(), k = argc;
  }
  if (mesh.empty() || !(resolution >= 1)) {
    std::fprintf(stderr,
                 "usage: envelope_bench [--variant grid|envelope|vdb-udf|vdb-sdf] "
                 "[--resolution R] [--repeat N] [--threads T] [--write OUT.obj] MESH\n");
    return 2;
  }
  try {
    return run(mesh, variant, resolution, repeat, write, threads);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "envelope_bench: %s\n", e.what());
    return 1;
  }
}
