#include <cstdio>
#include <fstream>
#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "core/input_error.h"
#include "core/io/mesh_file.h"
#include "core/report_json.h"

namespace spheremap::cli {
namespace {

const char* const kUsage = R"(Usage: spheremap map INPUT -o OUTPUT [--metrics FILE.json] [options]

Maps a closed genus-0 mesh (.obj, .off, .glb, .gltf; Draco-compressed glTF too) onto the
unit sphere, without folds. OUTPUT has the input's vertices in the input's order and the
input's faces, every vertex moved to its point on the sphere (vertices with equal
positions share one point). A glTF input is every triangle primitive of its default
scene in world space, unless --mesh picks one mesh.

  -o, --output FILE         the spherical mesh: .obj, or .glb (triangles, normals = positions,
                            the metrics in the mesh's extras); required
  --mesh INDEX|NAME         glTF: map only this mesh (by index or name)
  --metrics FILE            write the quality metrics as JSON
  --quiet                   no progress on stderr (shown for runs over a second)

)";

// Progress lines on stderr once a run has taken a second, at most twice a second.
MapControl progress_printer(bool quiet, double& last_print) {
  MapControl control;
  if (quiet) return control;
  control.on_progress = [&last_print](const MapProgress& p) {
    if (p.elapsed_seconds < 1.0 || p.elapsed_seconds - last_print < 0.5) return;
    last_print = p.elapsed_seconds;
    std::fprintf(stderr,
                 "spheremap: %5.1f s  %-9s level %d/%d (%zu vertices)  iteration %zu  folds %zu\n",
                 p.elapsed_seconds, std::string(p.stage).c_str(), p.level, p.levels, p.vertices,
                 p.iteration, p.folds);
  };
  return control;
}

}  // namespace

int run_map(int argc, char** argv) {
  std::set<std::string> values = kMapValueOptions;
  values.insert({"output", "metrics", "mesh"});
  std::set<std::string> flags = kMapFlags;
  flags.insert({"quiet", "help"});
  Arguments args(argc, argv, 2, values, flags);
  if (args.flag("help")) {
    std::cout << kUsage << kMapOptionsHelp
              << "\nExit codes: 0 bijective map written; 1 usage error; 2 invalid input (the\n"
                 "failed check on stderr); 3 no bijective map reached (the map and metrics are\n"
                 "still written, with \"bijective\": false and the folds left).\n";
    return kExitOk;
  }
  if (args.positional().size() != 1) throw UsageError("map takes exactly one INPUT file");
  if (!args.has("output")) throw UsageError("map needs -o OUTPUT");
  PrepareOptions prepare;
  MapOptions options;
  read_map_options(args, prepare, options);

  const PolygonMesh input = read_mesh_file(args.positional()[0], gltf_options(args));
  double last_print = 0;
  const MappedMesh mapped =
      map_mesh(input, prepare, options, progress_printer(args.flag("quiet"), last_print));
  const nlohmann::json metrics = metrics_json(mapped, options);
  write_mesh_file(args.text("output", ""), sphere_on_input(input, mapped), metrics, true);
  if (args.has("metrics")) {
    std::ofstream out(args.text("metrics", ""));
    out << metrics.dump(2) << "\n";
    if (!out) throw InputError("io", "cannot write '" + args.text("metrics", "") + "'");
  }
  if (!mapped.map.check.bijective) {
    std::fprintf(stderr, "spheremap: no bijective map reached (%s): %zu folded triangles left\n",
                 std::string(to_string(mapped.map.stop_reason)).c_str(), mapped.map.check.folds);
    return kExitNotBijective;
  }
  return kExitOk;
}

}  // namespace spheremap::cli
