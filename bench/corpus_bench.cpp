// corpus_bench: maps each mesh in a child process (so peak memory is that mesh's own) and
// prints a Markdown table: V, F, method, iterations, wall seconds (read + validate + map +
// verify + metrics), peak RSS, folds, bijective, distortion.
//
//   corpus_bench [--repeat N] [--paper-cap N] [--paper-seconds S] MESH.obj ...
//
// The default method runs --repeat times (default 3) and reports the fastest run: the
// machine's timing noise is large, the work is deterministic.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/io/mesh_file.h"
#include "core/map/pipeline.h"

namespace {

using namespace spheremap;

struct Row {
  double seconds = 0;
  size_t vertices = 0, faces = 0, iterations = 0, attempts = 0, folds = 0, degenerate = 0;
  double work = 0, min_area = 0, area_mean = 0, k_mean = 0, k_p99 = 0, stretch = 0;
  int bijective = 0, float32 = 0, ok = 0;
};

Row run_one(const std::string& path, const MapOptions& options) {
  Row row;
  const auto start = std::chrono::steady_clock::now();
  const PolygonMesh mesh = read_mesh_file(path);
  const MappedMesh m = map_mesh(mesh, {}, options);
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  row.vertices = m.prepared.topology.vertices;
  row.faces = m.prepared.topology.faces;
  row.iterations = m.map.iterations;
  row.attempts = m.map.attempts;
  row.work = m.map.fine_iteration_equivalents;
  row.folds = m.map.check.folds;
  row.degenerate = m.map.check.degenerate;
  row.min_area = m.map.check.min_signed_area;
  row.bijective = m.map.check.bijective;
  row.float32 = m.float32_check.bijective;
  row.area_mean = m.quality.area_log_ratio.mean;
  row.k_mean = m.quality.dilatation.mean;
  row.k_p99 = m.quality.dilatation.p99;
  row.stretch = m.quality.stretch_l2;
  row.ok = 1;
  return row;
}

// Runs in a child; returns the row and the child's peak RSS in KiB.
Row run_isolated(const std::string& path, const MapOptions& options, long& peak_kib) {
  int fds[2];
  if (pipe(fds) != 0) std::abort();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Row row;
    try {
      row = run_one(path, options);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "corpus_bench: %s: %s\n", path.c_str(), e.what());
    }
    if (write(fds[1], &row, sizeof row) != static_cast<ssize_t>(sizeof row)) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  Row row;
  if (read(fds[0], &row, sizeof row) != static_cast<ssize_t>(sizeof row)) row.ok = 0;
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  peak_kib = usage.ru_maxrss;
  return row;
}

std::string name_of(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  return name.substr(0, name.find('.'));
}

}  // namespace

int main(int argc, char** argv) {
  size_t paper_cap = 5000;
  int repeat = 3;
  double paper_seconds = 120;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--paper-cap" && i + 1 < argc)
      paper_cap = std::strtoul(argv[++i], nullptr, 10);
    else if (arg == "--paper-seconds" && i + 1 < argc)
      paper_seconds = std::atof(argv[++i]);
    else
      meshes.push_back(arg);
  }
  std::printf(
      "| mesh | V | F | method | attempts | iterations | work | wall s | peak MiB | B/face | folds "
      "| "
      "degenerate | min area | bijective | float32 | area mean abs(log) | K mean | K p99 | "
      "stretch L2 |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : meshes) {
    for (int paper = 0; paper < 2; ++paper) {
      MapOptions options;
      if (paper) {
        options.method = Method::kPaper;
        options.smoothing.placement = OffsetPlacement::kPaper;
        options.smoothing.limit_weight = 1.0;
        options.max_iterations = paper_cap;
        options.time_limit_seconds = paper_seconds;
      }
      long peak = 0;
      Row r = run_isolated(path, options, peak);
      for (int k = 1; k < (paper ? 1 : repeat) && r.ok; ++k) {
        long again_peak = 0;
        const Row again = run_isolated(path, options, again_peak);
        if (again.ok && again.seconds < r.seconds) r.seconds = again.seconds;
        peak = std::max(peak, again_peak);
      }
      if (!r.ok) {
        std::printf("| %s | | | %s | failed to run | | | | | | | | | | | | | | |\n",
                    name_of(path).c_str(), paper ? "paper" : "default");
        continue;
      }
      std::printf(
          "| %s | %zu | %zu | %s | %zu | %zu | %.1f | %.3f | %.1f | %.0f | %zu | %zu | %.1e | %s | "
          "%s | %.2f | %.2f | %.1f | %.2f |\n",
          name_of(path).c_str(), r.vertices, r.faces, paper ? "paper" : "default",
          paper ? size_t{0} : r.attempts, r.iterations, r.work, r.seconds, peak / 1024.0,
          peak * 1024.0 / static_cast<double>(r.faces), r.folds, r.degenerate, r.min_area,
          r.bijective ? "yes" : "**no**", r.bijective ? (r.float32 ? "yes" : "**no**") : "-",
          r.area_mean, r.k_mean, r.k_p99, r.stretch);
      std::fflush(stdout);
    }
  }
}
