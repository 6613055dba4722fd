// The service's configuration: built-in defaults, then a JSON file, then SPHEREMAP_*
// environment variables, then command-line flags, each overriding the one before.
// Every key is documented in config/spheremap.json and the README.
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace spheremap::server {

struct ServerConfig {
  std::string host = "127.0.0.1";  // "0.0.0.0" for all interfaces (the container does)
  int port = 8080;                 // 0: any free port (tests)
  // A second port for /healthz, /readyz and /metrics only, with threads of its own, so a
  // probe is answered while clients hold every API connection. -1: none; 0: any free port.
  int health_port = -1;
  // Where jobs wait: "memory://" (this process only; a restart loses them) or
  // "redis://HOST[:PORT][/DB]", shared by every replica and worker node on that Redis.
  std::string queue = "memory://";
  double visibility_timeout_seconds = 30;  // redis: a silent worker's job is reclaimed after
  int max_attempts = 3;                    // redis: starts of a job whose worker keeps dying
  // redis: a command carrying a payload (a submission's prepared input, a job's results)
  // may take this long plus this much per MiB before Redis counts as unavailable.
  double redis_payload_timeout_seconds = 5;
  double redis_payload_timeout_seconds_per_mib = 0.25;
  int workers = -1;                    // jobs mapped at once; -1 = the machine's cores; 0 = none
                                       // (an API-only node; redis queue only)
  int threads_per_job = 0;             // engine threads per job; 0 = cores / workers (at least 1)
  int http_threads = 16;               // requests handled at once (not connections; no mesh work)
  int intake_threads = 0;              // submitted meshes read and checked at once; 0 = cores
  double intake_timeout_seconds = 30;  // for one submission's wait and reading (503 beyond)
  size_t queue_capacity = 32;          // jobs waiting for a worker; more get 429
  size_t max_body_bytes = 64u << 20;   // queued inputs stay under queue_capacity x this
  size_t max_vertices = 2'000'000;     // of the mesh as sent (before welding; STL: after)
  size_t max_faces = 4'000'000;        // triangles of the mesh as sent (an n-gon is n - 2)
  // The voxels of one envelope grid (prepare wrap and auto), built while a submission is
  // prepared: about 10 bytes each at the peak, so 2^24 is about 170 MB per intake thread.
  // The default wrap_resolution (256) needs at most 3.5 million; larger grids get 422.
  size_t max_envelope_voxels = size_t{1} << 24;
  // Bytes of glTF buffers and images held while one submission is read (each distinct
  // source once); 413 beyond. At most twice the body is ever needed, so the cap in use is
  // the lower of this and 2 x the request's body.
  size_t max_resource_bytes = 256u << 20;
  // Pixels of the distinct base-colour images a remesh decodes for its colour bake; a
  // remesh job over it is refused (413) at submission.
  size_t max_image_pixels = size_t{1} << 26;
  double job_time_limit_seconds = 300;
  double result_ttl_seconds = 3600;          // finished jobs are kept this long...
  size_t result_memory_bytes = 1024u << 20;  // ...and within this many artifact bytes
  size_t max_jobs_kept = 10000;              // finished jobs kept at most, whatever their size
  double sync_timeout_seconds = 30;          // POST /v1/map waits this long, then answers 202
  double shutdown_grace_seconds = 30;        // on SIGTERM: time for queued and running jobs
  double keep_alive_timeout_seconds = 5;
  double read_timeout_seconds = 30;  // a client that stalls while sending is dropped
  // Whole-request limits of a connection (api/connection_limits.h): 408 / 431 / 429.
  double header_timeout_seconds = 10;      // first byte to the end of the headers
  double body_timeout_seconds = 120;       // end of the headers to the body's last byte
  size_t max_header_count = 100;           // request line and header lines
  size_t max_header_bytes = 32u << 10;     // all of them together
  size_t max_connections_per_address = 8;  // held at once; 0 = no cap
  // The API port's event front (api/event_front.h): connections held at once in all
  // (503 beyond), bytes of requests received and not yet answered, all connections
  // together (503 beyond; 0 = 4 x max_body_bytes), and the least pace at which a client
  // must take a response after read_timeout_seconds of grace.
  size_t max_connections = 4096;
  size_t request_buffer_bytes = 0;
  double response_min_bytes_per_second = 16384;
  // A file of `TENANT KEY` lines: every /v1 route then needs `Authorization: Bearer KEY`
  // and a job is seen only by its tenant. "" = no keys (ids are the only handle).
  std::string api_keys;
  size_t tenant_max_queued = 16;                   // jobs waiting, per tenant (429 beyond)
  size_t tenant_max_running = 0;                   // jobs mapping at once per tenant; 0 = no cap
  size_t tenant_result_memory_bytes = 256u << 20;  // finished results kept per tenant
  // Origins whose pages may call the API (CORS): "" (default: none; the page at / is on
  // the API's own origin and needs none), "*" for any, or a comma-separated list.
  std::string cors_origins;
  // Addresses of reverse proxies in front of the service, comma-separated: a request from
  // one of them is the client's named last in X-Forwarded-For (not a proxy of this list)
  // for tenants, quotas and logs. "" = none: the peer's address is the client's.
  std::string trusted_proxies;
  // "process" (default): each job in a child process (worker_process.h); "thread": in the
  // server process (no isolation; a crash in the engine takes the server down).
  std::string worker_isolation = "process";
  std::string worker_executable;   // "" = the server's own binary
  size_t worker_memory_bytes = 0;  // address space of a worker; 0 = 3/4 of physical memory
  // Expected peak memory of this node's running jobs together (server/memory_budget.h);
  // 0 = 3/4 of physical memory. A job that does not fit waits.
  size_t jobs_memory_bytes = 0;
  double worker_cpu_seconds = 0;  // CPU time of a worker; 0 = (2 x job limit + 60 s) x threads

  bool shared_queue() const { return queue.starts_with("redis://"); }
  // The resolved worker and thread counts for this machine.
  int effective_workers() const;
  int effective_threads_per_job() const;
  int effective_intake_threads() const;
  size_t effective_worker_memory_bytes() const;
  size_t effective_jobs_memory_bytes() const;
  double effective_worker_cpu_seconds() const;
  nlohmann::json to_json() const;  // with the resolved counts, for the start-up log
};

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Applies a JSON object of settings (unknown keys and out-of-range values are errors that
// name the key and `source`).
void apply_json(ServerConfig& config, const nlohmann::json& settings, const std::string& source);

// Applies SPHEREMAP_<KEY> variables (KEY = the setting in upper case) from `environment`.
void apply_environment(ServerConfig& config, const std::map<std::string, std::string>& environment);

// Applies one setting given as text (a flag or a variable).
void apply_setting(ServerConfig& config, const std::string& key, const std::string& value,
                   const std::string& source);

// Reads and applies a JSON configuration file.
void apply_file(ServerConfig& config, const std::string& path);

// The names of every setting, in the order of the documentation.
const std::vector<std::string>& setting_names();

}  // namespace spheremap::server
