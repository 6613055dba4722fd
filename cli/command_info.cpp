#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "core/io/mesh_file.h"
#include "core/outputs/report_json.h"

namespace spheremap::cli {

int run_info(int argc, char** argv) {
  Arguments args(argc, argv, 2, {"weld-tolerance", "mesh"}, {"help"});
  if (args.flag("help")) {
    std::cout << "Usage: spheremap info INPUT [--weld-tolerance T] [--mesh INDEX|NAME]\n\n"
                 "Prints the topology report of INPUT (.obj, .off, .glb, .gltf) as JSON: vertices, "
                 "edges,\n"
                 "faces, face sizes, boundary, manifoldness, orientation, components, genus,\n"
                 "and whether it can be mapped (with the failed checks). Exit 0 when it can,\n"
                 "2 when it cannot.\n";
    return kExitOk;
  }
  if (args.positional().size() != 1) throw UsageError("info takes exactly one INPUT file");
  PrepareOptions prepare;
  prepare.weld_tolerance = args.number("weld-tolerance", 0, 0, 1);
  const PreparedMesh prepared =
      prepare_mesh(read_mesh_file(args.positional()[0], gltf_options(args)), prepare);
  const nlohmann::json report = topology_json(prepared);
  std::cout << report.dump(2) << "\n";
  return report["mappable"].get<bool>() ? kExitOk : kExitInvalidInput;
}

}  // namespace spheremap::cli
