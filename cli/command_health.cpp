// spheremap health: asks a running service whether it is ready (GET /readyz), for
// container health checks without curl in the image. Exit 0 ready, 1 not.
#include <httplib.h>

#include <cstdio>
#include <iostream>

#include "cli/arguments.h"
#include "cli/commands.h"

namespace spheremap::cli {

int run_health(int argc, char** argv) {
  Arguments args(argc, argv, 2, {"host", "port", "timeout"}, {"help"});
  if (args.flag("help")) {
    std::cout << "Usage: spheremap health [--host H] [--port N] [--timeout S]\n\n"
                 "Exit 0 when the service at H:N (default 127.0.0.1 and $SPHEREMAP_PORT or 8080)\n"
                 "answers GET /readyz with 200 within S seconds (default 3), else 1.\n";
    return kExitOk;
  }
  const char* env_port = std::getenv("SPHEREMAP_PORT");
  const long long default_port = env_port ? std::atoll(env_port) : 8080;
  httplib::Client client(args.text("host", "127.0.0.1"),
                         static_cast<int>(args.integer("port", default_port, 1, 65535)));
  const double timeout = args.number("timeout", 3, 0.1, 600);
  const auto duration = std::chrono::milliseconds(static_cast<long long>(timeout * 1000));
  client.set_connection_timeout(duration);
  client.set_read_timeout(duration);
  const auto result = client.Get("/readyz");
  if (!result) {
    std::fprintf(stderr, "spheremap: health: no answer (%s)\n",
                 httplib::to_string(result.error()).c_str());
    return 1;
  }
  if (result->status != 200) {
    std::fprintf(stderr, "spheremap: health: /readyz answered %d\n", result->status);
    return 1;
  }
  return kExitOk;
}

}  // namespace spheremap::cli
