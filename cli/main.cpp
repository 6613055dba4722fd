// spheremap: maps closed genus-0 meshes onto the unit sphere. Subcommands: map, info,
// remesh, uv, morph, serve, worker.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "cli/map_options.h"
#include "cli/openmp_wait.h"
#include "core/io/mesh_file.h"
#include "core/mesh/input_error.h"
#include "server/worker_process.h"

namespace {

const char* const kHelp = R"(spheremap: fold-free spherical maps of closed genus-0 meshes

Usage:
  spheremap map INPUT -o OUTPUT [--metrics FILE.json] [options]   map onto the unit sphere
  spheremap info INPUT                                             topology report as JSON
  spheremap remesh INPUT -o OUT.glb [--resolution N]               octahedral remesh
  spheremap uv INPUT -o OUT.glb                                    texture coordinates
  spheremap morph INPUT -o OUT.glb                                 mesh-to-sphere morph
  spheremap serve [--config FILE] [--port N]                       the HTTP service
  spheremap worker --queue redis://HOST:PORT                       a worker node (no HTTP API)
  spheremap health [--port N]                                      is the service ready?
  spheremap COMMAND --help                                         options of a command
  spheremap --version

Exit codes: 0 success; 1 usage error; 2 invalid input; 3 no bijective map reached;
4 an output could not be written (or another error).
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace spheremap::cli;
  prefer_passive_openmp_wait(argv);
  const std::string command = argc > 1 ? argv[1] : "--help";
  try {
    if (command == "map") return run_map(argc, argv);
    if (command == "info") return run_info(argc, argv);
    if (command == "serve") return run_serve(argc, argv);
    if (command == "worker") return run_worker(argc, argv);
    if (command == "remesh") return run_remesh(argc, argv);
    if (command == "uv") return run_uv(argc, argv);
    if (command == "morph") return run_morph(argc, argv);
    if (command == "health") return run_health(argc, argv);
    // Internal: the service runs each job in `spheremap worker-process` (server/worker_process.h).
    if (command == "worker-process") return spheremap::server::worker_process_main();
    if (command == "--version") {
      std::puts("spheremap 0.1.0");
      return kExitOk;
    }
    if (command == "--help" || command == "-h" || command == "help") {
      std::fputs(kHelp, stdout);
      return kExitOk;
    }
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "spheremap: %s (see spheremap --help)\n", e.what());
    return kExitUsage;
  } catch (const TimeLimitError& e) {
    std::fprintf(stderr, "spheremap: time_limit: %s\n", e.what());
    return kExitNotBijective;
  } catch (const spheremap::InputError& e) {
    std::fprintf(stderr, "spheremap: invalid input [%s]: %s\n", e.check().c_str(), e.what());
    if (!e.fix().empty()) std::fprintf(stderr, "  fix: %s\n", fix_hint(e.fix()).c_str());
    return kExitInvalidInput;
  } catch (const spheremap::OutputError& e) {
    std::fprintf(stderr, "spheremap: output error: %s\n", e.what());
    return kExitOutputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "spheremap: error: %s\n", e.what());
    return kExitOutputError;
  }
}
