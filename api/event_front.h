// The event-driven front of the API listener: one thread that accepts connections and
// holds them, however many and however slow, while their requests arrive, and hands only
// whole requests (head and body buffered) to the pool, where cpp-httplib parses and
// routes them as before (FrontStream). What a response's writes leave unsent (a client
// that reads slowly or never) comes back here and is sent as the socket takes it. A
// thread is thus held for a handler's run, not for a client's pace.
//
// Per connection: the header deadline (from the request's first byte), the body deadline
// (from the head's end), the header caps and the declared body cap (RequestHeadScanner),
// the keep-alive idle time between requests, and the response deadline (ResponsePace).
// Per client address: at most max_connections_per_address held at once (loopback and
// the exempt proxies not counted). In all: at most max_connections held, and at most
// request_buffer_bytes of requests received and not yet answered (503 beyond).
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/connection_limits.h"
#include "api/front_stream.h"
#include "api/pending_output.h"
#include "api/request_head.h"

namespace spheremap::api {

struct FrontSettings {
  ConnectionLimits limits;
  std::chrono::steady_clock::duration keep_alive = std::chrono::seconds(5);
  size_t keep_alive_max_count = 100;  // requests per connection
  ResponsePace pace;
  size_t threads = 4;  // of the pool: requests handed to it at once
  size_t max_connections = 4096;
  size_t request_buffer_bytes = size_t{256} << 20;
  // Copies of response bytes queued for slow readers (shared artifacts are queued by
  // reference, not copied): per connection, and in all.
  size_t max_copied_per_connection = size_t{256} << 10;
  size_t response_copy_bytes = size_t{64} << 20;
  // Asked when a head has ended and its body has not arrived (on the event thread: it
  // must be quick): a whole answer refuses the request at once (sent, then the
  // connection closes, the body unread); nullopt waits for the body. For the checks the
  // service makes before reading a body (API key, Content-Encoding).
  std::function<std::optional<std::string>(std::string_view head, const std::string& peer)>
      check_head;
};

class EventFront {
 public:
  using Clock = std::chrono::steady_clock;
  // Serves the one request `stream` reads (on a pool thread); true when the connection
  // may carry another. `close_after`: answer with "Connection: close".
  using Serve = std::function<bool(FrontStream& stream, bool close_after)>;
  // Told of every connection a limit ends (the problem's slug, the peer's address).
  using RefusalObserver = std::function<void(const std::string& slug, const std::string& address)>;

  EventFront(FrontSettings settings, Serve serve, RefusalObserver observer);
  ~EventFront();
  EventFront(const EventFront&) = delete;
  EventFront& operator=(const EventFront&) = delete;

  // Accepts on `listener` and serves through `pool` until `listener` reads INVALID_SOCKET
  // (httplib's stop() swaps it so); then shuts the pool down (its running requests end)
  // and closes every connection.
  void run(const std::atomic<socket_t>& listener, httplib::TaskQueue& pool);

 private:
  struct Connection;
  struct Done;

  void accept_all(socket_t listener);
  bool admit(const std::string& address);
  void release(const std::string& address);
  void on_readable(Connection& c);
  void on_writable(Connection& c);
  // Scans what `c` has received; dispatches a whole request, refuses a broken one.
  void advance(Connection& c);
  // Queues a whole request for a thread (in its address's line), and starts what may.
  void dispatch(Connection& c);
  void pump();
  void start(Connection& c, httplib::TaskQueue& pool);
  void finish_response(Connection& c);
  void take_done();
  void check_deadlines();
  void refuse(Connection& c, int status, const char* reason, const std::string& slug,
              const std::string& detail, bool retry_after = false);
  // Stops answering: half-closes, then drops what the client still sends for a moment,
  // so the answer is not lost to a reset.
  void linger(Connection& c);
  void close(Connection& c);
  // Closes with a reset: for a client that did not take its answer in time.
  void abort(Connection& c);
  void watch(Connection& c, uint32_t events);

  FrontSettings settings_;
  Serve serve_;
  RefusalObserver observer_;
  int epoll_ = -1;
  int wake_ = -1;  // eventfd: a pool thread finished a request
  httplib::TaskQueue* pool_ = nullptr;
  std::map<int, std::unique_ptr<Connection>> connections_;
  std::map<std::string, size_t> per_address_;
  std::map<std::string, std::deque<Connection*>> ready_;  // whole requests, per address
  std::deque<std::string> turns_;  // addresses with a request ready, next first
  size_t busy_ = 0;                // requests on the pool
  size_t held_ = 0;                // request bytes received and not yet answered, all connections
  std::atomic<long long> copy_budget_;
  Clock::time_point accept_paused_until_{};
  bool accept_paused_ = false;
  std::mutex done_mutex_;
  std::vector<Done> done_;
};

}  // namespace spheremap::api
