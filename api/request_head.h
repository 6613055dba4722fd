// Where one HTTP/1.1 request ends in the bytes a connection has received, found as they
// arrive (the event front, api/event_front.h, holds a connection until its request is
// whole): the head ends at its blank line, the body is Content-Length bytes after it.
// The header caps of ConnectionLimits are applied on the way (431), and a declared body
// over max_body_bytes is refused (413) as soon as the head ends.
//
// Bodies in Transfer-Encoding (chunked) are not delimited here: the service refuses them
// (411, api/routes.cpp) before reading any, so such a request is whole at its head and
// its connection closes after the answer.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "api/connection_limits.h"

namespace spheremap::api {

class RequestHeadScanner {
 public:
  enum class State { kIncomplete, kComplete, kRefused };
  struct Refusal {
    int status = 0;           // 431 or 413
    const char* reason = "";  // the status line's text
    std::string slug;         // "too_many_headers", "headers_too_large", "too_large"
    std::string detail;
  };

  explicit RequestHeadScanner(const ConnectionLimits& limits) : limits_(&limits) {}

  // Scans `received` (the connection's unread bytes, this request's first byte first;
  // each call passes the same bytes with more appended) from where the last call stopped.
  // kComplete once the head and its declared body are all there: request_bytes() of
  // `received` are this request, the rest is the next (pipelined) one.
  State scan(std::string_view received);
  // Forgets the request: the next scan starts a new one.
  void reset() { *this = RequestHeadScanner(*limits_); }

  bool head_complete() const { return head_complete_; }
  size_t head_bytes() const { return head_bytes_; }  // through the blank line
  unsigned long long content_length() const { return content_length_; }
  // head + declared body (valid once head_complete()).
  size_t request_bytes() const { return head_bytes_ + static_cast<size_t>(content_length_); }
  bool has_transfer_encoding() const { return transfer_encoding_; }
  bool expects_continue() const { return expects_continue_; }  // Expect: 100-continue
  const Refusal& refusal() const { return refusal_; }

 private:
  State refuse(int status, const char* reason, std::string slug, std::string detail);
  void end_of_line();

  const ConnectionLimits* limits_;
  size_t scanned_ = 0;  // bytes of the head looked at
  size_t lines_ = 0;
  size_t line_length_ = 0;  // bytes of the current line before its '\n' (no '\r')
  std::string line_start_;  // its first bytes, lower case: enough to name the header
  bool head_complete_ = false;
  size_t head_bytes_ = 0;
  unsigned long long content_length_ = 0;
  bool has_length_ = false;
  bool transfer_encoding_ = false;
  bool expects_continue_ = false;
  Refusal refusal_;
};

}  // namespace spheremap::api
