#include "api/shared_body.h"

#include <algorithm>

#include "api/front_stream.h"

namespace spheremap::api {
namespace {

// What one write hands the socket: small enough to keep the send buffer short.
constexpr size_t kChunkBytes = size_t{64} << 10;

}  // namespace

void send_shared(httplib::Response& response, SharedBytes bytes, const std::string& content_type) {
  const size_t size = bytes->size();
  response.set_content_provider(
      size, content_type,
      [bytes = std::move(bytes)](size_t offset, size_t length, httplib::DataSink& sink) {
        // Lent to the event front: what a slow client has not taken yet is queued as a
        // reference to these bytes, and the thread goes back to the pool.
        lend_response_bytes(bytes, bytes->data(), bytes->size());
        return sink.write(bytes->data() + offset, std::min(length, kChunkBytes));
      });
}

}  // namespace spheremap::api
