// libFuzzer target: the bytes a client sends on one connection, read by the service's
// connection layer (GuardedStream: deadlines, header caps, pipelining) and cpp-httplib's
// request parser behind it, with a few routes of the API's shapes (GET, POST with a body,
// a path capture, the problem error handler). Any bytes must end in answers and a closed
// connection, never a crash or a hang.
//
// The input goes through a socket pair, as from a socket: one thread writes it and shuts
// the sending side, another drains the answers, the fuzzer's thread serves the other end.
// Then the same bytes go over TCP to a second server with the API port's event front
// (api/event_front.h: the request scanner, the pool hand-over, FrontStream, the queue
// of unsent bytes), which must answer and close just the same.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <thread>

#include "api/guarded_server.h"
#include "api/problem.h"

namespace {

void configure(spheremap::api::GuardedServer* s) {
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
}

spheremap::api::GuardedServer& server() {
  static spheremap::api::GuardedServer* instance = [] {
    auto* s = new spheremap::api::GuardedServer();
    configure(s);
    s->bind_to_any_port("127.0.0.1");  // serve_connection reads further requests only then
    return s;
  }();
  return *instance;
}

// The event-front server's port (listening on a thread of its own for the whole run).
int front_port() {
  static const int port = [] {
    auto* s = new spheremap::api::GuardedServer();
    configure(s);
    s->new_task_queue = [] { return new httplib::ThreadPool(2); };
    s->use_event_front(spheremap::api::FrontSettings{});
    const int bound = s->bind_to_any_port("127.0.0.1");
    std::thread([s] { s->listen_after_bind(); }).detach();
    while (!s->is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return bound;
  }();
  return port;
}

void through_the_front(const uint8_t* data, size_t size) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(front_port()));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return;
  }
  std::thread client([&] {
    size_t sent = 0;
    while (sent < size) {
      const ssize_t n = send(fd, data + sent, size - sent, MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<size_t>(n);
    }
    shutdown(fd, SHUT_WR);
  });
  char sink[4096];
  while (recv(fd, sink, sizeof sink, 0) > 0) {
  }
  client.join();
  close(fd);
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
  through_the_front(data, size);
  return 0;
}
