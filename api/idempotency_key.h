// The Idempotency-Key request header (IETF draft-ietf-httpapi-idempotency-key-header):
// a client names a submission, so that retrying it after a lost answer or a 503 cannot
// queue the job twice. The key is scoped to the tenant that sent it.
#pragma once

#include <httplib.h>

#include <string>

namespace spheremap::api {

inline constexpr size_t kMaxIdempotencyKeyLength = 255;

// The request's key ("" when it sends none): a Structured Field string ("...") or the bare
// text, 1 to 255 printable ASCII characters. Anything else, or the header twice, throws
// a 400 Problem (invalid_idempotency_key) that says what is wrong.
std::string idempotency_key_of(const httplib::Request& request);

}  // namespace spheremap::api
