#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <optional>

#include "cli/arguments.h"
#include "cli/commands.h"
#include "server/config.h"
#include "server/serve.h"

namespace spheremap::cli {
namespace {

const char* const kUsage =
    R"(Usage: spheremap serve [--config FILE] [--port N] [--host ADDRESS] [--SETTING VALUE ...]

Runs the HTTP mapping service (API: GET /v1/openapi.yaml). Settings come from the
built-in defaults, then the JSON file of --config (or $SPHEREMAP_CONFIG), then
SPHEREMAP_<SETTING> environment variables (e.g. SPHEREMAP_PORT=9000), then these flags;
the effective configuration is logged at start. config/spheremap.json documents every
setting with its default. Logs are JSON lines on stderr. SIGTERM or SIGINT drains the
jobs (shutdown_grace_seconds) and exits 0.

  --config FILE             a JSON file of settings
  --port N                  TCP port (default 8080; 0 = any free port, logged)
  --health-port N           a second port for /healthz, /readyz and /metrics only, with
                            threads of its own (default -1 = none; 0 = any free port)
  --host ADDRESS            listen address (default 127.0.0.1; 0.0.0.0 = all interfaces)
  --queue URL               memory:// (default: jobs live in this process) or
                            redis://HOST[:PORT][/DB]: jobs shared by every replica and
                            worker node on that Redis; any replica answers for any job
  --visibility-timeout-seconds S  redis: a job whose worker is silent this long is
                            reclaimed by another worker (default 30)
  --max-attempts N          redis: starts of a job whose worker keeps dying before it
                            fails as worker_crashed (default 3)
  --redis-payload-timeout-seconds S, --redis-payload-timeout-seconds-per-mib S
                            redis: how long a submission or a job's results may take to
                            store: S plus S per MiB (defaults 5, 0.25)
  --workers N               jobs mapped at once (default -1 = the machine's cores;
                            0 = none: an API-only node of a redis queue)
  --threads-per-job N       engine threads per job (default 0 = cores / workers)
  --queue-capacity N        jobs waiting at most; more get 429 (default 32)
  --max-body-bytes N        largest request body (default 67108864)
  --max-vertices N, --max-faces N
                            largest mesh accepted (default 2000000 / 4000000)
  --max-resource-bytes N    glTF buffers and images held while one upload is read, each
                            distinct buffer, file or image once (default 268435456; the
                            lower of this and 2 x the body applies); 413 beyond
  --max-image-pixels N      pixels of the distinct base-colour images a remesh decodes
                            for its colour bake (default 67108864); 413 beyond
  --job-time-limit-seconds S  per job (default 300)
  --result-ttl-seconds S, --result-memory-bytes N, --max-jobs-kept N
                            how long and how much finished results are kept (defaults
                            3600 s, 1 GiB, 10000 jobs); older ones are evicted (410 Gone)
  --sync-timeout-seconds S  POST /v1/map waits at most this long, then answers 202 (30)
  --shutdown-grace-seconds S  time given to jobs on SIGTERM before they are cancelled (30)
  --api-keys FILE           `TENANT KEY` lines: every /v1 route then needs
                            'Authorization: Bearer KEY'; a job is seen only by its tenant
  --tenant-max-queued N, --tenant-max-running N, --tenant-result-memory-bytes N
                            per tenant (API key, or client address): jobs waiting (16),
                            mapping at once (0 = no cap), results kept (256 MiB)
  --cors-origins LIST       origins whose pages may call the API: * for any, or
                            a comma-separated list (default none)
  --trusted-proxies LIST    reverse proxies whose X-Forwarded-For names the client
                            (comma-separated addresses; default none)
  --worker-isolation process|thread
                            each job in a child process (default), or in the server
  --worker-memory-bytes N, --worker-cpu-seconds S
                            limits of one worker process (defaults: 3/4 of RAM;
                            (2 x job limit + 60 s) x threads per job)
  --http-threads N, --keep-alive-timeout-seconds S, --read-timeout-seconds S
                            connection handling (16, 5 s, 30 s)
)";

std::string flag_name(std::string setting) {
  std::replace(setting.begin(), setting.end(), '_', '-');
  return setting;
}

std::map<std::string, std::string> spheremap_environment() {
  std::map<std::string, std::string> out;
  for (char** entry = environ; *entry; ++entry) {
    const std::string text = *entry;
    const size_t equals = text.find('=');
    if (text.starts_with("SPHEREMAP_") && equals != std::string::npos)
      out[text.substr(0, equals)] = text.substr(equals + 1);
  }
  return out;
}

const char* const kWorkerUsage =
    R"(Usage: spheremap worker --queue redis://HOST[:PORT][/DB] [--workers N] [--SETTING VALUE ...]

Runs a worker node: takes jobs from the Redis queue that `spheremap serve --queue ...`
replicas fill, maps each in a worker process, and stores the results there; no public
HTTP port (--health-port N serves /healthz, /readyz and /metrics). Takes every setting
of `spheremap serve --help`. SIGTERM lets running jobs finish for shutdown_grace_seconds,
then puts what is left back in the queue for another node, and exits 0.
)";

// Settings from the defaults, the --config file (or $SPHEREMAP_CONFIG), SPHEREMAP_*
// variables and flags, in that order; null after printing --help.
std::optional<server::ServerConfig> read_config(int argc, char** argv, const char* usage) {
  std::set<std::string> values = {"config"};
  for (const std::string& name : server::setting_names()) values.insert(flag_name(name));
  Arguments args(argc, argv, 2, values, {"help"});
  if (args.flag("help")) {
    std::cout << usage;
    return std::nullopt;
  }
  if (!args.positional().empty())
    throw UsageError(std::string(argv[1]) + " takes no positional arguments");
  server::ServerConfig config;
  const auto environment = spheremap_environment();
  try {
    std::string file = args.text("config", "");
    if (file.empty() && environment.count("SPHEREMAP_CONFIG"))
      file = environment.at("SPHEREMAP_CONFIG");
    if (!file.empty()) server::apply_file(config, file);
    server::apply_environment(config, environment);
    for (const std::string& name : server::setting_names())
      if (args.has(flag_name(name)))
        server::apply_setting(config, name, args.text(flag_name(name), ""), "--" + flag_name(name));
  } catch (const server::ConfigError& e) {
    throw UsageError(std::string("configuration: ") + e.what());
  }
  return config;
}

}  // namespace

int run_serve(int argc, char** argv) {
  const auto config = read_config(argc, argv, kUsage);
  return config ? server::serve(*config) : kExitOk;
}

int run_worker(int argc, char** argv) {
  const auto config = read_config(argc, argv, kWorkerUsage);
  if (!config) return kExitOk;
  if (!config->shared_queue())
    throw UsageError("worker needs a shared queue: --queue redis://HOST:PORT");
  if (config->effective_workers() == 0) throw UsageError("worker needs --workers of 1 or more");
  return server::serve(*config, server::Role::kWorker);
}

}  // namespace spheremap::cli
