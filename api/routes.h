// The HTTP API (documented in api/openapi.yaml, served at /v1/openapi.yaml): routes,
// limits and handlers installed on a cpp-httplib server. Handlers only parse, check and
// answer; mapping runs in the service's workers (server/).
#pragma once

#include <httplib.h>

#include "api/backend.h"
#include "api/guarded_server.h"

namespace spheremap::api {

// Installs every route, the body limit, timeouts, the connection limits, the thread
// count, the request log and the error and exception handlers (problem+json, never an
// exception's text in a header).
void install_api(GuardedServer& http, Backend& service);

// Only /healthz, /readyz and /metrics, with two threads and short timeouts of their own:
// for the health port, which answers while every API connection is held.
void install_health(GuardedServer& http, Backend& service);

// The OpenAPI document, embedded at build time.
extern const char* const kOpenApiYaml;

}  // namespace spheremap::api
