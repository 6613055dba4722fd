// What one client connection may cost the service before a handler runs: how long its
// headers and body may take, how many header lines and bytes it may send, and how many
// connections one address may have served at once. cpp-httplib 0.11 bounds only each
// single recv() (read_timeout), which a client trickling a byte a second never trips;
// GuardedServer (guarded_server.h) enforces these on the socket itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace spheremap::api {

struct ConnectionLimits {
  // From a request's first byte to the blank line that ends its headers: beyond, 408.
  double header_timeout_seconds = 10;
  // From the end of the headers to the body's last byte: beyond, 408. 120 s carries the
  // largest default body (64 MiB) at 0.5 MiB/s.
  double body_timeout_seconds = 120;
  // The request line and header lines of one request, and their bytes: beyond, 431.
  size_t max_header_count = 100;
  size_t max_header_bytes = 32u << 10;
  // A body declared (Content-Length) larger than this is answered 413 as soon as the
  // headers end, not read and discarded first (cpp-httplib reads it all).
  size_t max_body_bytes = SIZE_MAX;
  // Connections served at once for one client address; 0 = no cap. Beyond, the new
  // connection is answered 429 at once and closed. Loopback and `exempt` addresses (the
  // trusted reverse proxies, which carry many clients) are not counted.
  size_t max_connections_per_address = 8;
  std::vector<std::string> exempt;
};

}  // namespace spheremap::api
