#include "api/event_front.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "api/log.h"
#include "api/problem.h"

namespace spheremap::api {
namespace {

using Clock = EventFront::Clock;

constexpr size_t kReadChunk = size_t{64} << 10;
constexpr auto kTick = std::chrono::milliseconds(50);
constexpr auto kLinger = std::chrono::seconds(2);
constexpr std::string_view kContinue = "HTTP/1.1 100 Continue\r\n\r\n";

// The epoll tags of the two descriptors that are not connections.
char listener_tag;
char wake_tag;

// A reverse proxy on the same host connects from here; a local client could exhaust the
// machine by other means anyway.
bool is_loopback(const std::string& address) {
  return address == "127.0.0.1" || address == "::1" || address == "::ffff:127.0.0.1";
}

std::string numeric_address(const sockaddr_storage& address, socklen_t length) {
  char host[NI_MAXHOST] = {};
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&address), length, host, sizeof host, nullptr,
                    0, NI_NUMERICHOST) != 0)
    return "";
  return host;
}

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

std::string problem_answer(int status, const char* reason, const std::string& slug,
                           const std::string& detail, bool retry_after) {
  const std::string body = problem_json(Problem(status, slug, reason, detail)).dump() + "\n";
  std::string answer = "HTTP/1.1 " + std::to_string(status) + " ";
  answer += reason;
  answer += "\r\nContent-Type: application/problem+json\r\n";
  if (retry_after) answer += "Retry-After: 1\r\n";
  answer += "Content-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n";
  return answer + body;
}

std::string seconds_text(double value) {
  std::string text = std::to_string(value);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text + " s";
}

}  // namespace

struct EventFront::Connection {
  enum class State { kReading, kServing, kWriting, kLingering };
  explicit Connection(const ConnectionLimits& limits) : scanner(limits) {}

  int fd = -1;
  std::string address;
  bool counted = false;  // in per_address_
  State state = State::kReading;
  uint32_t events = 0;  // watched now (0: not in the epoll set)
  std::string in;       // received, not yet handed to a pool thread
  RequestHeadScanner scanner;
  size_t held = 0;      // of held_: bytes of requests received here, not yet answered
  std::string request;  // whole, waiting for a thread
  bool continue_sent = false;
  Clock::time_point idle_since = Clock::now();
  Clock::time_point request_start{}, body_start{};
  size_t served = 0;
  bool close_after_write = false;
  PendingOutput out;
  Clock::time_point handed_back{}, progress{};
  size_t sent = 0;
  Clock::time_point linger_until{};
};

struct EventFront::Done {
  Connection* connection;
  bool keep;
  bool failed;  // its writes failed or ran past their deadline
  PendingOutput out;
};

EventFront::EventFront(FrontSettings settings, Serve serve, RefusalObserver observer)
    : settings_(std::move(settings)),
      serve_(std::move(serve)),
      observer_(std::move(observer)),
      copy_budget_(static_cast<long long>(settings_.response_copy_bytes)) {}

EventFront::~EventFront() {
  for (auto& [fd, c] : connections_) ::close(fd);
  if (wake_ >= 0) ::close(wake_);
  if (epoll_ >= 0) ::close(epoll_);
}

void EventFront::watch(Connection& c, uint32_t events) {
  if (events == c.events) return;
  epoll_event event{};
  event.events = events;
  event.data.ptr = &c;
  const int op = c.events == 0 ? EPOLL_CTL_ADD : events == 0 ? EPOLL_CTL_DEL : EPOLL_CTL_MOD;
  ::epoll_ctl(epoll_, op, c.fd, &event);
  c.events = events;
}

bool EventFront::admit(const std::string& address) {
  const ConnectionLimits& limits = settings_.limits;
  if (limits.max_connections_per_address == 0 || is_loopback(address) ||
      std::find(limits.exempt.begin(), limits.exempt.end(), address) != limits.exempt.end())
    return true;
  size_t& count = per_address_[address];
  if (count >= limits.max_connections_per_address) return false;
  ++count;
  return true;
}

void EventFront::release(const std::string& address) {
  const auto entry = per_address_.find(address);
  if (entry == per_address_.end()) return;
  if (--entry->second == 0) per_address_.erase(entry);
}

void EventFront::run(const std::atomic<socket_t>& listener, httplib::TaskQueue& pool) {
  pool_ = &pool;
  epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
  wake_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  const socket_t listening = listener.load();
  // Accepted until none is waiting: the listening socket must not block.
  ::fcntl(listening, F_SETFL, ::fcntl(listening, F_GETFL) | O_NONBLOCK);
  // cpp-httplib listens with a backlog of 5: a burst of connections beyond it waits a
  // SYN retransmission (1 s), even while this thread is idle. Listening again sets it.
  ::listen(listening, SOMAXCONN);
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.ptr = &wake_tag;
  ::epoll_ctl(epoll_, EPOLL_CTL_ADD, wake_, &event);
  event.data.ptr = &listener_tag;
  ::epoll_ctl(epoll_, EPOLL_CTL_ADD, listening, &event);

  std::vector<epoll_event> ready(256);
  Clock::time_point next_check = Clock::now() + kTick;
  while (listener.load() != INVALID_SOCKET) {
    const int n = ::epoll_wait(epoll_, ready.data(), static_cast<int>(ready.size()),
                               static_cast<int>(kTick.count()));
    for (int i = 0; i < n; ++i) {
      void* tag = ready[static_cast<size_t>(i)].data.ptr;
      const uint32_t what = ready[static_cast<size_t>(i)].events;
      if (tag == &listener_tag) {
        accept_all(listening);
      } else if (tag == &wake_tag) {
        uint64_t count;
        (void)!::read(wake_, &count, sizeof count);
      } else {
        Connection& c = *static_cast<Connection*>(tag);
        if (c.state == Connection::State::kWriting && (what & (EPOLLOUT | EPOLLERR | EPOLLHUP)))
          on_writable(c);
        else if (what & (EPOLLIN | EPOLLERR | EPOLLHUP))
          on_readable(c);
      }
    }
    take_done();
    const Clock::time_point now = Clock::now();
    if (now >= next_check) {
      next_check = now + kTick;
      check_deadlines();
      if (accept_paused_ && now >= accept_paused_until_) {
        accept_paused_ = false;
        epoll_event again{};
        again.events = EPOLLIN;
        again.data.ptr = &listener_tag;
        ::epoll_ctl(epoll_, EPOLL_CTL_MOD, listening, &again);
      }
    }
  }
  // Requests running on the pool end (their writes are bounded by the response
  // deadline); then every connection closes.
  pool.shutdown();
  {
    std::lock_guard lock(done_mutex_);
    done_.clear();
  }
  for (auto& [fd, c] : connections_) ::close(fd);
  connections_.clear();
}

void EventFront::accept_all(socket_t listener) {
  for (int k = 0; k < 256; ++k) {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    const int fd = ::accept4(listener, reinterpret_cast<sockaddr*>(&address), &length,
                             SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        // Out of descriptors: stop accepting for a moment rather than spin on the listener.
        accept_paused_ = true;
        accept_paused_until_ = Clock::now() + std::chrono::milliseconds(100);
        epoll_event none{};
        none.data.ptr = &listener_tag;
        ::epoll_ctl(epoll_, EPOLL_CTL_MOD, listener, &none);
        log_event({{"event", "accept_paused"}, {"error", std::strerror(errno)}});
      }
      return;
    }
    int yes = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    auto owned = std::make_unique<Connection>(settings_.limits);
    Connection& c = *owned;
    c.fd = fd;
    c.address = numeric_address(address, length);
    connections_.emplace(fd, std::move(owned));
    if (connections_.size() > settings_.max_connections) {
      refuse(c, 503, "Service Unavailable", "too_many_connections",
             "the server holds max_connections (" + std::to_string(settings_.max_connections) +
                 ") connections; retry shortly",
             true);
      continue;
    }
    if (!admit(c.address)) {
      refuse(c, 429, "Too Many Requests", "too_many_connections",
             "this address already has max_connections_per_address (" +
                 std::to_string(settings_.limits.max_connections_per_address) +
                 ") connections open; reuse one (keep-alive) or retry after it ends",
             true);
      continue;
    }
    c.counted = true;
    watch(c, EPOLLIN);
  }
}

void EventFront::on_readable(Connection& c) {
  char buffer[kReadChunk];
  for (int k = 0; k < 4; ++k) {
    const ssize_t got = ::recv(c.fd, buffer, sizeof buffer, 0);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (got <= 0) {  // the client is gone (or half-closed: nothing more will come)
      close(c);
      return;
    }
    if (c.state == Connection::State::kLingering) continue;  // dropped
    if (c.in.empty() && !c.scanner.head_complete()) c.request_start = Clock::now();
    c.in.append(buffer, static_cast<size_t>(got));
    c.held += static_cast<size_t>(got);
    held_ += static_cast<size_t>(got);
    if (held_ > settings_.request_buffer_bytes) {
      refuse(c, 503, "Service Unavailable", "request_buffer_full",
             "the server holds request_buffer_bytes (" +
                 std::to_string(settings_.request_buffer_bytes) +
                 ") of requests being received; retry shortly",
             true);
      return;
    }
    advance(c);
    if (c.state != Connection::State::kReading) return;
  }
}

void EventFront::advance(Connection& c) {
  const bool head_was_complete = c.scanner.head_complete();
  const RequestHeadScanner::State state = c.scanner.scan(c.in);
  if (state == RequestHeadScanner::State::kRefused) {
    const auto& refusal = c.scanner.refusal();
    refuse(c, refusal.status, refusal.reason, refusal.slug, refusal.detail);
    return;
  }
  if (c.scanner.head_complete() && !head_was_complete) {
    c.body_start = Clock::now();
    if (state == RequestHeadScanner::State::kIncomplete && settings_.check_head) {
      const std::optional<std::string> answer =
          settings_.check_head(std::string_view(c.in).substr(0, c.scanner.head_bytes()), c.address);
      if (answer) {
        (void)!::send(c.fd, answer->data(), answer->size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        linger(c);
        return;
      }
    }
    if (state == RequestHeadScanner::State::kIncomplete && c.scanner.expects_continue() &&
        !c.continue_sent) {
      c.continue_sent = true;
      (void)!::send(c.fd, kContinue.data(), kContinue.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    }
  }
  if (state == RequestHeadScanner::State::kComplete) dispatch(c);
}

void EventFront::dispatch(Connection& c) {
  const size_t size = c.scanner.request_bytes();
  if (c.in.size() == size) {
    c.request = std::move(c.in);
    c.in.clear();
  } else {
    c.request = c.in.substr(0, size);
    c.in.erase(0, size);
  }
  ++c.served;
  watch(c, 0);
  c.state = Connection::State::kServing;
  // Waits for a thread in its address's line: threads go to the addresses in turn, so
  // however many requests one client has ready, another's waits for one of them at most.
  std::deque<Connection*>& line = ready_[c.address];
  if (line.empty()) turns_.push_back(c.address);
  line.push_back(&c);
  pump();
}

void EventFront::pump() {
  while (busy_ < settings_.threads && !turns_.empty()) {
    const std::string address = std::move(turns_.front());
    turns_.pop_front();
    const auto line = ready_.find(address);
    Connection& c = *line->second.front();
    line->second.pop_front();
    if (line->second.empty())
      ready_.erase(line);
    else
      turns_.push_back(address);
    ++busy_;
    start(c, *pool_);
  }
}

void EventFront::start(Connection& c, httplib::TaskQueue& pool) {
  // Chunked bodies are refused unread (request_head.h): nothing after such a head is a
  // request, so the connection closes after the answer.
  const bool close_after =
      c.scanner.has_transfer_encoding() || c.served >= settings_.keep_alive_max_count;
  Connection* connection = &c;
  const Clock::time_point start = c.request_start;
  const bool continue_sent = c.continue_sent;
  std::string request = std::move(c.request);
  c.request.clear();
  pool.enqueue([this, connection, request = std::move(request), close_after, start,
                continue_sent]() mutable {
    FrontStream stream(connection->fd, std::move(request), connection->address, start,
                       settings_.pace, settings_.max_copied_per_connection, copy_budget_,
                       continue_sent);
    stream.bind_to_this_thread();
    bool keep = false;
    try {
      keep = serve_(stream, close_after) && !stream.failed() && !close_after;
    } catch (...) {
      keep = false;
    }
    if (stream.timed_out())
      log_event({{"event", "response_abandoned"},
                 {"remote", connection->address},
                 {"bytes", stream.bytes_written()},
                 {"reason", "the client did not read the response within its deadline"}});
    {
      std::lock_guard lock(done_mutex_);
      done_.push_back({connection, keep, stream.failed(), stream.take_pending()});
    }
    const uint64_t one = 1;
    (void)!::write(wake_, &one, sizeof one);
  });
}

void EventFront::take_done() {
  std::vector<Done> done;
  {
    std::lock_guard lock(done_mutex_);
    done.swap(done_);
  }
  for (Done& d : done) {
    --busy_;
    Connection& c = *d.connection;
    // The request went with its thread; what is left is the next one's start.
    held_ -= c.held - c.in.size();
    c.held = c.in.size();
    c.out = std::move(d.out);
    c.close_after_write = !d.keep;
    c.handed_back = c.progress = Clock::now();
    c.sent = 0;
    if (d.failed) {
      abort(c);
    } else if (c.out.empty()) {
      finish_response(c);
    } else {
      c.state = Connection::State::kWriting;
      watch(c, EPOLLOUT);
    }
  }
  pump();
}

void EventFront::on_writable(Connection& c) {
  const size_t copied = c.out.copied();
  const size_t before = c.sent;
  const bool ok = c.out.send_some(c.fd, c.sent);
  copy_budget_.fetch_add(static_cast<long long>(copied - c.out.copied()));
  if (!ok) {
    close(c);
    return;
  }
  if (c.sent > before) c.progress = Clock::now();
  if (c.out.empty()) finish_response(c);
}

void EventFront::finish_response(Connection& c) {
  if (c.close_after_write) {
    linger(c);
    return;
  }
  c.state = Connection::State::kReading;
  c.scanner.reset();
  c.continue_sent = false;
  c.idle_since = c.request_start = Clock::now();
  watch(c, EPOLLIN);
  if (!c.in.empty()) advance(c);  // a pipelined request, already here
}

void EventFront::check_deadlines() {
  const Clock::time_point now = Clock::now();
  const ConnectionLimits& limits = settings_.limits;
  std::vector<Connection*> expired;
  for (auto& [fd, c] : connections_) {
    switch (c->state) {
      case Connection::State::kReading:
        if (c->in.empty() && !c->scanner.head_complete()) {
          if (now - c->idle_since >= settings_.keep_alive) expired.push_back(c.get());
        } else if (!c->scanner.head_complete()) {
          if (now - c->request_start >= seconds(limits.header_timeout_seconds))
            expired.push_back(c.get());
        } else if (now - c->body_start >= seconds(limits.body_timeout_seconds)) {
          expired.push_back(c.get());
        }
        break;
      case Connection::State::kWriting:
        if (now - c->progress >= settings_.pace.stall ||
            now >= settings_.pace.deadline(c->handed_back, c->sent + c->out.bytes()))
          expired.push_back(c.get());
        break;
      case Connection::State::kLingering:
        if (now >= c->linger_until) expired.push_back(c.get());
        break;
      case Connection::State::kServing:
        break;
    }
  }
  for (Connection* c : expired) {
    if (c->state == Connection::State::kReading && c->in.empty() && !c->scanner.head_complete()) {
      close(*c);  // idle between requests: closed without an answer
    } else if (c->state == Connection::State::kReading && !c->scanner.head_complete()) {
      refuse(*c, 408, "Request Timeout", "header_timeout",
             "the request's headers did not arrive within header_timeout_seconds (" +
                 seconds_text(limits.header_timeout_seconds) + ")");
    } else if (c->state == Connection::State::kReading) {
      refuse(*c, 408, "Request Timeout", "body_timeout",
             "the request's body did not arrive within body_timeout_seconds (" +
                 seconds_text(limits.body_timeout_seconds) + ")");
    } else if (c->state == Connection::State::kWriting) {
      log_event({{"event", "response_abandoned"},
                 {"remote", c->address},
                 {"bytes_sent", c->sent},
                 {"bytes_left", c->out.bytes()},
                 {"reason", "the client did not read the response within its deadline"}});
      abort(*c);
    } else {
      close(*c);
    }
  }
}

void EventFront::refuse(Connection& c, int status, const char* reason, const std::string& slug,
                        const std::string& detail, bool retry_after) {
  // Recorded before the client can see the answer.
  if (observer_) observer_(slug, c.address);
  const std::string answer = problem_answer(status, reason, slug, detail, retry_after);
  (void)!::send(c.fd, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  linger(c);
}

void EventFront::linger(Connection& c) {
  ::shutdown(c.fd, SHUT_WR);
  held_ -= c.held;
  c.held = 0;
  c.in.clear();
  c.in.shrink_to_fit();
  c.state = Connection::State::kLingering;
  c.linger_until = Clock::now() + kLinger;
  watch(c, EPOLLIN);
}

void EventFront::abort(Connection& c) {
  // A reset, not an orderly close: the kernel would otherwise keep the unsent bytes (up
  // to its send buffer, megabytes) for minutes, trying a client that does not read.
  const struct ::linger reset { 1, 0 };
  ::setsockopt(c.fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
  close(c);
}

void EventFront::close(Connection& c) {
  watch(c, 0);
  if (c.counted) release(c.address);
  held_ -= c.held;
  copy_budget_.fetch_add(static_cast<long long>(c.out.copied()));
  const int fd = c.fd;
  ::close(fd);
  connections_.erase(fd);  // destroys c
}

}  // namespace spheremap::api
