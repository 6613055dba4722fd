// libFuzzer target: the bytes a client sends on one connection, read by the service's
// connection layer (GuardedStream: deadlines, header caps, pipelining) and cpp-httplib's
// request parser behind it, with a few routes of the API's shapes (GET, POST with a body,
// a path capture, the problem error handler). Any bytes must end in answers and a closed
// connection, never a crash or a hang.
//
// The input goes through a socket pair, as from a socket: one thread writes it and shuts
// the sending side, another drains the answers, the fuzzer's thread serves the other end.
#include <sys/socket.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <thread>

#include "api/guarded_server.h"
#include "api/problem.h"

namespace {

spheremap::api::GuardedServer& server() {
  static spheremap::api::GuardedServer* instance = [] {
    auto* s = new spheremap::api::GuardedServer();
    spheremap::api::ConnectionLimits limits;
    limits.header_timeout_seconds = limits.body_timeout_seconds = 1;
    limits.max_body_bytes = 1 << 20;
    s->set_connection_limits(limits);
    s->set_read_timeout(std::chrono::milliseconds(200));
    s->set_write_timeout(std::chrono::milliseconds(200));
    s->set_keep_alive_timeout(1);
    s->set_payload_max_length(1 << 20);
    s->Get("/v1/jobs/([0-9a-f]{32})",
           [](const httplib::Request& request, httplib::Response& response) {
             response.set_content(request.matches[1].str(), "text/plain");
           });
    s->Post("/v1/jobs", [](const httplib::Request& request, httplib::Response& response) {
      response.set_content(
          std::to_string(request.body.size()) + " " + std::to_string(request.files.size()),
          "text/plain");
    });
    s->set_error_handler([](const httplib::Request& request, httplib::Response& response) {
      spheremap::api::send_problem(
          response, spheremap::api::Problem(response.status, "x", "X", "refused"), request.path);
    });
    s->bind_to_any_port("127.0.0.1");  // serve_connection reads further requests only then
    return s;
  }();
  return *instance;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, ends) != 0) return 0;
  std::thread client([&] {
    size_t sent = 0;
    while (sent < size) {
      const ssize_t n = send(ends[0], data + sent, size - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<size_t>(n);
    }
    shutdown(ends[0], SHUT_WR);
  });
  std::thread drain([&] {
    char sink[4096];
    while (recv(ends[0], sink, sizeof sink, 0) > 0) {
    }
  });
  server().serve_connection(ends[1]);  // closes ends[1]
  client.join();
  drain.join();
  close(ends[0]);
  return 0;
}
