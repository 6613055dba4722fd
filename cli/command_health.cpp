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
                 "Exit 0 when the service at H:N answers GET /readyz with 200 within S seconds\n"
                 "(default 3), else 1. Default H:N: 127.0.0.1 and $SPHEREMAP_HEALTH_PORT when it\n"
                 "is a port (a worker node has no API port), else $SPHEREMAP_PORT, else 8080.\n";
    return kExitOk;
  }
  // The image's HEALTHCHECK runs this with no flags, for API replicas and worker nodes
  // alike: the health port when one is set, else the API port.
  const char* env_health = std::getenv("SPHEREMAP_HEALTH_PORT");
  const char* env_port = std::getenv("SPHEREMAP_PORT");
  long long default_port = env_port ? std::atoll(env_port) : 8080;
  if (env_health && std::atoll(env_health) > 0) default_port = std::atoll(env_health);
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
