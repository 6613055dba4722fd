// One client connection as cpp-httplib reads and writes it, with the limits of
// ConnectionLimits applied while a request arrives: a deadline for the headers and one
// for the body (whatever the pace of single reads), a cap on header lines and bytes.
// A request that breaks one is answered here (408 or 431, problem+json, Connection:
// close) and every later read and write fails, so cpp-httplib gives the connection up
// without writing an answer of its own.
//
// The stream lives as long as the connection, not one request: bytes read ahead of the
// current request (a pipelined next request) stay in its buffer for the next one.
#pragma once

#include <httplib.h>

#include <array>
#include <chrono>
#include <functional>
#include <string>

#include "api/connection_limits.h"
#include "api/served_connection.h"

namespace spheremap::api {

class GuardedStream final : public httplib::Stream, public ServedConnection {
 public:
  // `io_timeout` bounds each single wait for the socket (cpp-httplib's read and write
  // timeouts); the deadlines of `limits` bound a request's headers and body as a whole.
  GuardedStream(socket_t socket, const ConnectionLimits& limits, Clock::duration io_timeout);

  // Starts the next request on the connection: the header clock runs from now.
  void begin_request();
  // When the current request's first bytes were there (begin_request).
  Clock::time_point request_start() const override { return request_start_; }
  // The peer's numeric address ("" if the socket has none).
  const std::string& peer_address() const override { return peer_address_; }
  // Called with the problem slug as a limit is broken, before the answer is written, so
  // whatever it records is there before the client can see the answer.
  void on_refusal(std::function<void(const std::string& slug)> callback) {
    on_refusal_ = std::move(callback);
  }
  // Bytes of a next request are already here (no need to wait for the socket).
  bool has_buffered() const { return begin_ < end_; }
  // A limit was broken and answered: the connection must close.
  bool refused() const override { return refused_; }
  // Its problem slug ("header_timeout", ...), once refused.
  const std::string& refusal() const { return refusal_; }

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return socket_; }

 private:
  enum class Phase { kHeaders, kBody };

  Clock::time_point deadline() const;
  // Counts header bytes and lines among the `size` bytes about to be handed out; false
  // (after answering 431) when they break a cap.
  bool account(const char* bytes, size_t size);
  // Writes a problem answer and marks the connection refused.
  void refuse(int status, const char* reason, const std::string& slug, const std::string& detail);

  socket_t socket_;
  const ConnectionLimits& limits_;
  Clock::duration io_timeout_;
  Phase phase_ = Phase::kHeaders;
  Clock::time_point phase_start_ = Clock::now();
  Clock::time_point request_start_ = phase_start_;
  std::string peer_address_;
  std::function<void(const std::string&)> on_refusal_;
  size_t header_bytes_ = 0;
  size_t header_lines_ = 0;
  size_t line_length_ = 0;  // bytes of the current header line before its '\n'
  std::string line_start_;  // its first bytes, lower case: enough to see Content-Length
  unsigned long long declared_length_ = 0;
  bool refused_ = false;
  std::string refusal_;
  std::array<char, 4096> buffer_{};
  size_t begin_ = 0, end_ = 0;  // unread bytes are buffer_[begin_, end_)
};

}  // namespace spheremap::api
