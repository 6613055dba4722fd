// What the HTTP API needs of the service behind it, and nothing more: the settings its
// handlers enforce, the job queue, the API keys, the metrics and the readiness. The
// server implements it (server/service.h); the API never sees processes, threads of
// workers, Redis or configuration files, so the dependency goes one way: core <- api <-
// server.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "api/api_keys.h"
#include "api/connection_limits.h"
#include "api/intake.h"
#include "api/job_queue.h"
#include "api/service_metrics.h"

namespace spheremap::api {

// The limits and connection settings the API applies (a subset of the server's
// configuration, copied from it at start).
struct ApiSettings {
  int http_threads = 16;
  size_t queue_capacity = 32;
  size_t tenant_max_queued = 16;
  size_t max_body_bytes = 64u << 20;
  size_t max_vertices = 2'000'000;
  size_t max_faces = 4'000'000;
  size_t max_envelope_voxels = size_t{1} << 24;  // one envelope grid's voxels (wrap, auto)
  size_t max_resource_bytes = 256u << 20;        // glTF buffers and images held per submission
  size_t max_image_pixels = size_t{1} << 26;     // base-colour pixels a remesh decodes
  double sync_timeout_seconds = 30;
  double keep_alive_timeout_seconds = 5;
  double read_timeout_seconds = 30;
  ConnectionLimits connection;               // its `exempt` = trusted_proxies
  size_t max_connections = 4096;             // held by the event front at once
  size_t request_buffer_bytes = 256u << 20;  // requests being received, all connections
  double response_min_bytes_per_second = 16384;
  std::string cors_origins;                  // "" = no CORS headers at all
  std::vector<std::string> trusted_proxies;  // peers whose X-Forwarded-For is believed
  int workers = 0;                           // on this node, for /metrics
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const ApiSettings& settings() const = 0;
  virtual JobQueue& queue() = 0;
  virtual const ApiKeys& api_keys() const = 0;
  virtual ServiceMetrics& metrics() = 0;
  virtual Intake& intake() = 0;       // where submitted meshes are read and checked
  virtual bool ready() const = 0;     // new jobs may be submitted (/readyz)
  virtual bool draining() const = 0;  // told to stop: new jobs get 503 shutting_down
};

}  // namespace spheremap::api
