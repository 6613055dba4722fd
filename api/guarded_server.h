// cpp-httplib's Server with each connection served through a GuardedStream: header and
// body deadlines, header line and byte caps (connection_limits.h), a cap on connections
// served at once per client address, and pipelined requests kept (cpp-httplib 0.11 reads
// each request through a fresh buffer and drops bytes read ahead).
//
// It replaces the library's per-connection loop (Server::process_and_close_socket, a
// virtual the library calls for every accepted socket) and nothing else: routing,
// request parsing and response writing stay the library's (Server::process_request).
//
// With the event front on (use_event_front: the API port), the library's accept loop
// is replaced too: one thread holds every connection while its request arrives and
// while a slow client takes its answer (api/event_front.h); pool threads only run
// process_request on whole, buffered requests. Without it (the health port), a thread
// serves each connection to its end, as the library does.
#pragma once

#include <httplib.h>

#include <atomic>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "api/connection_limits.h"
#include "api/event_front.h"
#include "api/guarded_stream.h"
#include "api/served_connection.h"

namespace spheremap::api {

class GuardedServer : public httplib::Server {
 public:
  // Listens with SO_REUSEADDR only: the library's default adds SO_REUSEPORT, which lets a
  // second process bind a port already listening and take half its connections.
  GuardedServer();
  // Set before listening.
  void set_connection_limits(ConnectionLimits limits) { limits_ = std::move(limits); }
  const ConnectionLimits& connection_limits() const { return limits_; }
  // Told of every connection the limits end (the problem's slug, the peer's address), for
  // the log and the metrics: no handler and no request log sees those.
  using RefusalObserver = std::function<void(const std::string& slug, const std::string& address)>;
  void set_refusal_observer(RefusalObserver observer) { observer_ = std::move(observer); }
  // Serves through the event front, with these settings (its limits, keep-alive and
  // stall time are taken from this server's when listening). Set before listening.
  void use_event_front(FrontSettings settings) { front_ = std::move(settings); }

  // The library's, or the event front's loop when it is on (these hide the library's
  // non-virtual ones: call them on a GuardedServer).
  bool listen_after_bind();
  // The library's, also kept here: the event front applies the pre-routing handler (and
  // then the post-routing handler and the logger) to a head whose body has not arrived,
  // so what it refuses before reading a body is refused before the body is sent.
  GuardedServer& set_pre_routing_handler(HandlerWithResponse handler);
  GuardedServer& set_post_routing_handler(Handler handler);
  GuardedServer& set_logger(httplib::Logger logger);
  bool is_running() const { return front_running_ || httplib::Server::is_running(); }
  void stop();

  // Serves one accepted connection to its end and closes it: what the listener does for
  // every socket it accepts (public for the connection fuzzer, which hands it one end of
  // a socket pair; the server must be bound, or no second request is read).
  bool serve_connection(socket_t socket);

  // The connection this thread is serving now (nullptr off a connection thread): what the
  // request logger reads for requests the library gives up on before routing, which carry
  // neither a start time nor a remote address of their own.
  static const ServedConnection* stream_of_this_thread();

 private:
  bool process_and_close_socket(socket_t socket) override { return serve_connection(socket); }
  // Counts a connection from `address`; false when that address is at its cap.
  bool admit(const std::string& address);
  // The answer the pre-routing handler gives `head` alone, if it handles it.
  std::optional<std::string> answer_head(std::string_view head, const std::string& peer);
  void release(const std::string& address);

  ConnectionLimits limits_;
  RefusalObserver observer_;
  std::mutex mutex_;
  std::map<std::string, size_t> connections_;  // served now, per counted address
  std::optional<FrontSettings> front_;
  HandlerWithResponse pre_routing_;
  Handler post_routing_;
  httplib::Logger logger_;
  std::atomic<bool> front_running_{false};
};

}  // namespace spheremap::api
