#include <cstdio>
#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "core/io/mesh_file.h"
#include "core/mesh/input_error.h"
#include "core/outputs/report_json.h"

namespace spheremap::cli {

int run_info(int argc, char** argv) {
  Arguments args(argc, argv, 2, {"weld-tolerance", "mesh", "prepare"}, {"help"});
  if (args.flag("help")) {
    std::cout
        << "Usage: spheremap info INPUT [--weld-tolerance T] [--mesh INDEX|NAME]\n"
           "                      [--prepare exact|repair|parts|wrap]\n\n"
           "Prints the topology report of INPUT (.obj, .off, .stl, .ply, .drc, .glb, .gltf) as\n"
           "JSON: vertices, edges, faces, face sizes, boundary, manifoldness, orientation,\n"
           "components, genus, and whether it can be mapped (with the failed checks and,\n"
           "where an option would help, that option as \"fix\"). The top level describes the\n"
           "mesh that would be mapped, as --prepare leaves it (cleaned, holes filled, handles\n"
           "closed, parts or an envelope); \"input\" the file as read, before any of that, and\n"
           "\"preparation\" what was done. A file that cannot be read\n"
           "at all is still answered in JSON: {\"mappable\": false, \"error\": {\"check\", "
           "\"message\"}}.\n"
           "Exit 0 when it can be mapped, 1 usage error, 2 when it cannot be mapped or read.\n";
    return kExitOk;
  }
  if (args.positional().size() != 1) throw UsageError("info takes exactly one INPUT file");
  PrepareOptions prepare;
  prepare.weld_tolerance = args.number("weld-tolerance", 0, 0, 1);
  prepare.method = parse_prepare_method(args.text("prepare", "auto"));
  GltfReadStats stats;
  PolygonMesh input;
  try {
    input = read_mesh_file(args.positional()[0], gltf_options(args), &stats);
  } catch (const InputError& e) {
    // A pipeline reads the verdict from stdout whatever went wrong.
    nlohmann::json error = {{"check", e.check()}, {"message", e.what()}};
    if (!e.fix().empty()) error["fix"] = fix_json(e.fix());
    std::cout << nlohmann::json({{"mappable", false}, {"error", error}}).dump(2) << "\n";
    std::fprintf(stderr, "spheremap: invalid input [%s]: %s\n", e.check().c_str(), e.what());
    return kExitInvalidInput;
  }
  const nlohmann::json report = topology_json(prepare_input(input, nullptr, prepare), &stats);
  std::cout << report.dump(2) << "\n";
  return report["mappable"].get<bool>() ? kExitOk : kExitInvalidInput;
}

}  // namespace spheremap::cli
