#include "api/request_head.h"

#include <cctype>
#include <cstdlib>

namespace spheremap::api {
namespace {

// Enough of a line to hold "content-length: " and a 20-digit number, or "expect:
// 100-continue".
constexpr size_t kLineStartBytes = 48;

std::string_view value_of(std::string_view line, std::string_view name) {
  std::string_view value = line.substr(name.size());
  while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
  while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
  return value;
}

}  // namespace

RequestHeadScanner::State RequestHeadScanner::refuse(int status, const char* reason,
                                                     std::string slug, std::string detail) {
  refusal_ = {status, reason, std::move(slug), std::move(detail)};
  return State::kRefused;
}

void RequestHeadScanner::end_of_line() {
  ++lines_;
  const std::string_view line = line_start_;
  // The first of several Content-Length lines counts, as in cpp-httplib (which reads the
  // first with its name); its number as strtoull reads it, as cpp-httplib does.
  if (lines_ > 1 && line.starts_with("content-length:") && !has_length_) {
    has_length_ = true;
    content_length_ = std::strtoull(line_start_.c_str() + 15, nullptr, 10);
  } else if (lines_ > 1 && line.starts_with("transfer-encoding:")) {
    transfer_encoding_ = true;
  } else if (lines_ > 1 && line.starts_with("expect:")) {
    expects_continue_ = value_of(line, "expect:") == "100-continue";
  }
  line_length_ = 0;
  line_start_.clear();
}

RequestHeadScanner::State RequestHeadScanner::scan(std::string_view received) {
  if (refusal_.status != 0) return State::kRefused;
  for (; !head_complete_ && scanned_ < received.size(); ++scanned_) {
    const char c = received[scanned_];
    if (c == '\n') {
      // A blank line after the request line ends the head (a blank first line is
      // cpp-httplib's to reject).
      if (line_length_ == 0 && lines_ > 0) {
        head_complete_ = true;
        head_bytes_ = scanned_ + 1;
      }
      end_of_line();
    } else if (c != '\r') {
      ++line_length_;
      if (line_start_.size() < kLineStartBytes)
        line_start_.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
    if (head_complete_) break;
    if (lines_ > limits_->max_header_count)
      return refuse(431, "Request Header Fields Too Large", "too_many_headers",
                    "the request has more than max_header_count (" +
                        std::to_string(limits_->max_header_count) + ") header lines");
    if (scanned_ + 1 > limits_->max_header_bytes)
      return refuse(431, "Request Header Fields Too Large", "headers_too_large",
                    "the request's headers exceed max_header_bytes (" +
                        std::to_string(limits_->max_header_bytes) + " bytes)");
  }
  if (!head_complete_) return State::kIncomplete;
  if (transfer_encoding_) content_length_ = 0;  // refused unread; see the header
  if (content_length_ > limits_->max_body_bytes)
    return refuse(413, "Payload Too Large", "too_large",
                  "the request body is over max_body_bytes (" +
                      std::to_string(limits_->max_body_bytes) + " bytes)");
  return received.size() >= request_bytes() ? State::kComplete : State::kIncomplete;
}

}  // namespace spheremap::api
