#include "api/guarded_server.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <thread>

#include "api/guarded_stream.h"
#include "api/problem.h"

namespace spheremap::api {
namespace {

using Clock = GuardedStream::Clock;

thread_local const ServedConnection* serving = nullptr;

// A reverse proxy on the same host connects from here; a local client could exhaust the
// machine by other means anyway.
bool is_loopback(const std::string& address) {
  return address == "127.0.0.1" || address == "::1" || address == "::ffff:127.0.0.1";
}

// Waits up to `timeout` for a next request, in short steps so a stopping server is seen.
bool next_request_arrives(const std::atomic<socket_t>& server_socket, const GuardedStream& stream,
                          Clock::duration timeout) {
  if (stream.has_buffered()) return true;
  const Clock::time_point until = Clock::now() + timeout;
  while (server_socket != INVALID_SOCKET && Clock::now() < until) {
    pollfd entry{stream.socket(), POLLIN, 0};
    if (::poll(&entry, 1, 50) > 0) return true;
  }
  return false;
}

// Ends a connection so that an answer written just before reaches the client: the
// request bytes it already sent are read and dropped (closing with unread bytes would
// reset the connection and could discard the answer), at most 256 KiB, without waiting.
void close_connection(socket_t socket) {
  ::shutdown(socket, SHUT_WR);
  char sink[4096];
  for (int i = 0; i < 64 && ::recv(socket, sink, sizeof sink, MSG_DONTWAIT) > 0; ++i) {
  }
  ::close(socket);
}

void answer_too_many_connections(socket_t socket, size_t cap) {
  const std::string body =
      problem_json(Problem(429, "too_many_connections", "Too many connections",
                           "this address already has max_connections_per_address (" +
                               std::to_string(cap) +
                               ") connections being served; reuse one "
                               "(keep-alive) or retry after it ends"))
          .dump() +
      "\n";
  const std::string answer =
      "HTTP/1.1 429 Too Many Requests\r\nContent-Type: application/problem+json\r\n"
      "Retry-After: 1\r\nContent-Length: " +
      std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
  (void)!::send(socket, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

// The request line and header fields of `head` into `request` (method, target, path,
// query parameters, version, headers); false if it is not a request line.
bool parse_head(std::string_view head, httplib::Request& request) {
  size_t end = head.find('\n');
  if (end == std::string_view::npos) return false;
  std::string_view line = head.substr(0, end);
  if (line.ends_with('\r')) line.remove_suffix(1);
  const size_t first = line.find(' ');
  const size_t second = line.rfind(' ');
  if (first == std::string_view::npos || second == first) return false;
  request.method = std::string(line.substr(0, first));
  request.target = std::string(line.substr(first + 1, second - first - 1));
  request.version = std::string(line.substr(second + 1));
  const size_t query = request.target.find('?');
  request.path = httplib::detail::decode_url(request.target.substr(0, query), false);
  if (query != std::string::npos)
    httplib::detail::parse_query_text(request.target.substr(query + 1), request.params);
  for (size_t at = end + 1; at < head.size();) {
    end = head.find('\n', at);
    if (end == std::string_view::npos) end = head.size();
    std::string_view field = head.substr(at, end - at);
    at = end + 1;
    if (field.ends_with('\r')) field.remove_suffix(1);
    const size_t colon = field.find(':');
    if (field.empty() || colon == std::string_view::npos) continue;
    std::string_view value = field.substr(colon + 1);
    while (!value.empty() && (value.front() == ' ' || value.front() == '\t'))
      value.remove_prefix(1);
    while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
    request.headers.emplace(std::string(field.substr(0, colon)), std::string(value));
  }
  return true;
}

// The reason phrases of the answers given to a head alone (cpp-httplib 0.11 does not
// export its table).
const char* reason_of(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 411:
      return "Length Required";
    case 413:
      return "Payload Too Large";
    case 415:
      return "Unsupported Media Type";
    case 416:
      return "Range Not Satisfiable";
    case 429:
      return "Too Many Requests";
    case 503:
      return "Service Unavailable";
    default:
      return status < 400 ? "OK" : "Error";
  }
}

// `response` as bytes on the wire, with Connection: close (its request's body is left
// unread, so nothing after it on the connection is a request).
std::string serialize_closing(const httplib::Response& response) {
  std::string text = "HTTP/1.1 " + std::to_string(response.status) + " ";
  text += reason_of(response.status);
  text += "\r\n";
  for (const auto& [name, value] : response.headers) {
    if (name == "Content-Length" || name == "Connection") continue;
    text += name;
    text += ": ";
    text += value;
    text += "\r\n";
  }
  text +=
      "Content-Length: " + std::to_string(response.body.size()) + "\r\nConnection: close\r\n\r\n";
  return text + response.body;
}

}  // namespace

GuardedServer::GuardedServer() {
  // A restart may rebind a port with connections still in TIME_WAIT; a port another
  // socket listens on stays refused (EADDRINUSE), which SO_REUSEPORT would allow.
  set_socket_options([](socket_t socket) {
    int yes = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
}

bool GuardedServer::admit(const std::string& address) {
  if (limits_.max_connections_per_address == 0 || is_loopback(address) ||
      std::find(limits_.exempt.begin(), limits_.exempt.end(), address) != limits_.exempt.end())
    return true;
  std::lock_guard lock(mutex_);
  size_t& count = connections_[address];
  if (count >= limits_.max_connections_per_address) {
    if (count == 0) connections_.erase(address);
    return false;
  }
  ++count;
  return true;
}

void GuardedServer::release(const std::string& address) {
  std::lock_guard lock(mutex_);
  const auto entry = connections_.find(address);
  if (entry == connections_.end()) return;
  if (--entry->second == 0) connections_.erase(entry);
}

const ServedConnection* GuardedServer::stream_of_this_thread() {
  return serving;
}

bool GuardedServer::listen_after_bind() {
  if (!front_) return httplib::Server::listen_after_bind();
  FrontSettings settings = *front_;
  settings.limits = limits_;
  settings.keep_alive = std::chrono::seconds(std::max<time_t>(1, keep_alive_timeout_sec_));
  settings.keep_alive_max_count = keep_alive_max_count_;
  settings.check_head = [this](std::string_view head, const std::string& peer) {
    return answer_head(head, peer);
  };
  settings.pace.stall =
      std::chrono::seconds(write_timeout_sec_) + std::chrono::microseconds(write_timeout_usec_);
  EventFront front(
      std::move(settings),
      [this](FrontStream& stream, bool close_after) {
        serving = &stream;
        bool closed = false;
        const bool served = process_request(stream, close_after, closed, nullptr);
        serving = nullptr;
        return served && !closed;
      },
      [this](const std::string& slug, const std::string& address) {
        if (observer_) observer_(slug, address);
      });
  std::unique_ptr<httplib::TaskQueue> pool(new_task_queue());
  front_running_ = true;
  front.run(svr_sock_, *pool);
  front_running_ = false;
  return true;
}

GuardedServer& GuardedServer::set_pre_routing_handler(HandlerWithResponse handler) {
  pre_routing_ = handler;
  httplib::Server::set_pre_routing_handler(std::move(handler));
  return *this;
}

GuardedServer& GuardedServer::set_post_routing_handler(Handler handler) {
  post_routing_ = handler;
  httplib::Server::set_post_routing_handler(std::move(handler));
  return *this;
}

GuardedServer& GuardedServer::set_logger(httplib::Logger logger) {
  logger_ = logger;
  httplib::Server::set_logger(std::move(logger));
  return *this;
}

std::optional<std::string> GuardedServer::answer_head(std::string_view head,
                                                      const std::string& peer) {
  if (!pre_routing_) return std::nullopt;
  httplib::Request request;
  std::optional<std::string> answer;
  if (!parse_head(head, request)) return std::nullopt;  // the library's to answer, 400
  request.remote_addr = peer;
  httplib::Response response;
  if (pre_routing_(request, response) != HandlerResponse::Handled) return std::nullopt;
  if (response.status == -1) response.status = 200;
  if (post_routing_) post_routing_(request, response);
  if (logger_) logger_(request, response);
  return serialize_closing(response);
}

void GuardedServer::stop() {
  if (!front_running_) {
    httplib::Server::stop();
    return;
  }
  // The front sees the swap and ends its loop; the socket is shut (accept fails, the
  // loop wakes), and closed here once nothing may wait on it.
  const socket_t listening = svr_sock_.exchange(INVALID_SOCKET);
  if (listening == INVALID_SOCKET) return;
  ::shutdown(listening, SHUT_RDWR);
  while (front_running_) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::close(listening);
}

bool GuardedServer::serve_connection(socket_t socket) {
  const auto io_timeout =
      std::chrono::seconds(read_timeout_sec_) + std::chrono::microseconds(read_timeout_usec_);
  GuardedStream stream(socket, limits_, io_timeout);
  const std::string& address = stream.peer_address();
  if (!admit(address)) {
    answer_too_many_connections(socket, limits_.max_connections_per_address);
    close_connection(socket);
    if (observer_) observer_("too_many_connections", address);
    return false;
  }
  stream.on_refusal([this, &address](const std::string& slug) {
    if (observer_) observer_(slug, address);
  });
  serving = &stream;
  // The library's keep-alive loop, with one stream for the whole connection.
  bool served = false;
  for (size_t left = keep_alive_max_count_; left > 0; --left) {
    if (!next_request_arrives(svr_sock_, stream, std::chrono::seconds(keep_alive_timeout_sec_)))
      break;
    stream.begin_request();
    bool closed = false;
    served = process_request(stream, left == 1, closed, nullptr);
    if (!served || closed || stream.refused()) break;
  }
  serving = nullptr;
  release(address);
  close_connection(socket);
  return served;
}

}  // namespace spheremap::api
