#include "api/idempotency_key.h"

#include <algorithm>

#include "api/problem.h"

namespace spheremap::api {
namespace {

Problem invalid(const std::string& why) {
  return Problem(400, "invalid_idempotency_key", "Invalid Idempotency-Key",
                 "the Idempotency-Key header " + why +
                     "; send 1 to 255 printable ASCII characters, e.g. Idempotency-Key: "
                     "\"8e03978e-40d5-43e8-bc93-6894a57f9324\"");
}

}  // namespace

std::string idempotency_key_of(const httplib::Request& request) {
  const size_t count = request.get_header_value_count("Idempotency-Key");
  if (count == 0) return "";
  if (count > 1) throw invalid("is sent " + std::to_string(count) + " times");
  std::string key = request.get_header_value("Idempotency-Key");
  // The draft's form is an sf-string; the bare value is taken too (what clients send).
  if (key.size() >= 2 && key.front() == '"' && key.back() == '"') {
    key = key.substr(1, key.size() - 2);
    if (key.find_first_of("\"\\") != std::string::npos)
      throw invalid("holds a quote or a backslash inside its quotes");
  }
  if (key.empty()) throw invalid("is empty");
  if (key.size() > kMaxIdempotencyKeyLength)
    throw invalid("is " + std::to_string(key.size()) + " characters long");
  if (!std::all_of(key.begin(), key.end(), [](char c) { return c >= 0x20 && c <= 0x7e; }))
    throw invalid("holds a character that is not printable ASCII");
  return key;
}

}  // namespace spheremap::api
