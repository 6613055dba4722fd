#include "api/guarded_stream.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string_view>

#include "api/problem.h"

namespace spheremap::api {
namespace {

int milliseconds_until(GuardedStream::Clock::time_point deadline) {
  // Rounded up: a wait must not end just before the deadline it waits for.
  const auto left =
      std::chrono::ceil<std::chrono::milliseconds>(deadline - GuardedStream::Clock::now());
  return static_cast<int>(std::clamp<long long>(left.count(), 0, 1'000'000));
}

bool wait_for(socket_t socket, short events, int timeout_ms) {
  pollfd entry{socket, events, 0};
  int ready;
  do ready = ::poll(&entry, 1, timeout_ms);
  while (ready < 0 && errno == EINTR);
  return ready > 0;
}

std::string seconds_text(double seconds) {
  std::ostringstream text;
  text << seconds << " s";
  return text.str();
}

void name_of(const sockaddr_storage& address, socklen_t length, std::string& ip, int& port) {
  char host[NI_MAXHOST] = {};
  char service[NI_MAXSERV] = {};
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&address), length, host, sizeof host, service,
                    sizeof service, NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return;
  ip = host;
  port = std::atoi(service);
}

}  // namespace

GuardedStream::GuardedStream(socket_t socket, const ConnectionLimits& limits,
                             Clock::duration io_timeout)
    : socket_(socket), limits_(limits), io_timeout_(io_timeout) {
  int port = 0;
  get_remote_ip_and_port(peer_address_, port);
}

void GuardedStream::begin_request() {
  phase_ = Phase::kHeaders;
  phase_start_ = request_start_ = Clock::now();
  header_bytes_ = header_lines_ = line_length_ = 0;
  line_start_.clear();
  declared_length_ = 0;
}

GuardedStream::Clock::time_point GuardedStream::deadline() const {
  const double seconds =
      phase_ == Phase::kHeaders ? limits_.header_timeout_seconds : limits_.body_timeout_seconds;
  return phase_start_ +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

bool GuardedStream::is_readable() const {
  if (has_buffered()) return true;
  const Clock::time_point wait_until = std::min(deadline(), Clock::now() + io_timeout_);
  return wait_for(socket_, POLLIN, milliseconds_until(wait_until));
}

bool GuardedStream::is_writable() const {
  if (refused_) return false;
  // A peer that has closed reads as end of file: not writable any more (SSE streams end).
  if (wait_for(socket_, POLLIN, 0) && !has_buffered()) {
    char probe;
    if (::recv(socket_, &probe, 1, MSG_PEEK | MSG_DONTWAIT) <= 0) return false;
  }
  return wait_for(
      socket_, POLLOUT,
      static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(io_timeout_).count()));
}

ssize_t GuardedStream::read(char* ptr, size_t size) {
  if (refused_) return -1;
  // The deadline holds however the bytes are paced: checked before every read, not
  // only when a wait for the socket runs out.
  const Clock::time_point until = deadline();
  if (Clock::now() >= until) {
    const bool headers = phase_ == Phase::kHeaders;
    refuse(408, "Request Timeout", headers ? "header_timeout" : "body_timeout",
           headers ? "the request's headers did not arrive within header_timeout_seconds (" +
                         seconds_text(limits_.header_timeout_seconds) + ")"
                   : "the request's body did not arrive within body_timeout_seconds (" +
                         seconds_text(limits_.body_timeout_seconds) + ")");
    return -1;
  }
  if (!has_buffered()) {
    const Clock::time_point wait_until = std::min(until, Clock::now() + io_timeout_);
    if (!wait_for(socket_, POLLIN, milliseconds_until(wait_until)))
      return Clock::now() >= until ? read(ptr, size) : -1;  // 408 above, or the read timeout
    ssize_t received;
    do received = ::recv(socket_, buffer_.data(), buffer_.size(), 0);
    while (received < 0 && errno == EINTR);
    if (received <= 0) return received;
    begin_ = 0;
    end_ = static_cast<size_t>(received);
  }
  const size_t n = std::min(size, end_ - begin_);
  if (!account(buffer_.data() + begin_, n)) return -1;
  std::memcpy(ptr, buffer_.data() + begin_, n);
  begin_ += n;
  return static_cast<ssize_t>(n);
}

bool GuardedStream::account(const char* bytes, size_t size) {
  static constexpr std::string_view kLength = "content-length:";
  for (size_t i = 0; i < size && phase_ == Phase::kHeaders; ++i) {
    ++header_bytes_;
    const char c = bytes[i];
    if (c != '\n') {
      if (c == '\r') continue;
      ++line_length_;
      if (line_start_.size() < kLength.size() + 24)
        line_start_.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
      continue;
    }
    ++header_lines_;
    if (line_start_.starts_with(kLength))
      declared_length_ = std::strtoull(line_start_.c_str() + kLength.size(), nullptr, 10);
    if (line_length_ == 0 && header_lines_ > 1) {  // the blank line: headers end here
      phase_ = Phase::kBody;
      phase_start_ = Clock::now();
    }
    line_length_ = 0;
    line_start_.clear();
  }
  if (phase_ == Phase::kHeaders && header_lines_ > limits_.max_header_count) {
    refuse(431, "Request Header Fields Too Large", "too_many_headers",
           "the request has more than max_header_count (" +
               std::to_string(limits_.max_header_count) + ") header lines");
    return false;
  }
  if (phase_ == Phase::kHeaders && header_bytes_ > limits_.max_header_bytes) {
    refuse(431, "Request Header Fields Too Large", "headers_too_large",
           "the request's headers exceed max_header_bytes (" +
               std::to_string(limits_.max_header_bytes) + " bytes)");
    return false;
  }
  if (phase_ == Phase::kBody && declared_length_ > limits_.max_body_bytes) {
    refuse(413, "Payload Too Large", "too_large",
           "the request body is over max_body_bytes (" + std::to_string(limits_.max_body_bytes) +
               " bytes)");
    return false;
  }
  return true;
}

void GuardedStream::refuse(int status, const char* reason, const std::string& slug,
                           const std::string& detail) {
  const std::string body = problem_json(Problem(status, slug, reason, detail)).dump() + "\n";
  const std::string answer = "HTTP/1.1 " + std::to_string(status) + " " + reason +
                             "\r\nContent-Type: application/problem+json\r\nContent-Length: " +
                             std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
  if (on_refusal_) on_refusal_(slug);
  write(answer.data(), answer.size());
  refused_ = true;
  refusal_ = slug;
}

ssize_t GuardedStream::write(const char* ptr, size_t size) {
  if (refused_) return -1;
  size_t sent = 0;
  while (sent < size) {
    if (!wait_for(socket_, POLLOUT,
                  static_cast<int>(
                      std::chrono::duration_cast<std::chrono::milliseconds>(io_timeout_).count())))
      return -1;
    const ssize_t n = ::send(socket_, ptr + sent, size - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return -1;
    sent += static_cast<size_t>(n);
  }
  return static_cast<ssize_t>(size);
}

void GuardedStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (::getpeername(socket_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    name_of(address, length, ip, port);
}

void GuardedStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (::getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    name_of(address, length, ip, port);
}

}  // namespace spheremap::api
