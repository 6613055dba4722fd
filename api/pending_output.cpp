#include "api/pending_output.h"

#include <sys/socket.h>

#include <cerrno>
#include <string>

namespace spheremap::api {

void PendingOutput::push_reference(std::shared_ptr<const void> owner, const char* data,
                                   size_t size) {
  if (size == 0) return;
  segments_.push_back({std::move(owner), data, size, false});
  bytes_ += size;
}

void PendingOutput::push_copy(const char* data, size_t size) {
  if (size == 0) return;
  auto copy = std::make_shared<const std::string>(data, size);
  const char* bytes = copy->data();
  segments_.push_back({std::move(copy), bytes, size, true});
  bytes_ += size;
  copied_ += size;
}

bool PendingOutput::send_some(int socket, size_t& sent) {
  while (!segments_.empty()) {
    Segment& front = segments_.front();
    const ssize_t n = ::send(socket, front.data, front.size, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK;
    if (n == 0) return true;
    const size_t taken = static_cast<size_t>(n);
    sent += taken;
    bytes_ -= taken;
    if (front.copy) copied_ -= taken;
    front.data += taken;
    front.size -= taken;
    if (front.size == 0) segments_.pop_front();
  }
  return true;
}

}  // namespace spheremap::api
