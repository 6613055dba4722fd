#include "api/front_stream.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>

namespace spheremap::api {
namespace {

thread_local FrontStream* current = nullptr;

constexpr std::string_view kContinue = "HTTP/1.1 100 Continue\r\n\r\n";

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

ServedConnection::Clock::time_point ResponsePace::deadline(
    ServedConnection::Clock::time_point start, size_t bytes) const {
  const double rate = std::max(min_bytes_per_second, 1.0);
  return start + stall +
         std::chrono::duration_cast<ServedConnection::Clock::duration>(
             std::chrono::duration<double>(static_cast<double>(bytes) / rate));
}

FrontStream::FrontStream(socket_t socket, std::string request, const std::string& peer_address,
                         Clock::time_point request_start, const ResponsePace& pace,
                         size_t max_copied_bytes, std::atomic<long long>& copy_budget,
                         bool continue_sent)
    : socket_(socket),
      request_(std::move(request)),
      peer_address_(peer_address),
      request_start_(request_start),
      pace_(pace),
      max_copied_bytes_(max_copied_bytes),
      copy_budget_(copy_budget),
      drop_continue_(continue_sent) {}

FrontStream::~FrontStream() {
  if (current == this) current = nullptr;
  copy_budget_.fetch_add(static_cast<long long>(pending_.copied()));
}

FrontStream* FrontStream::of_this_thread() {
  return current;
}

void FrontStream::bind_to_this_thread() {
  current = this;
}

void FrontStream::lend(std::shared_ptr<const void> owner, const char* data, size_t size) {
  for (const Lent& lent : lent_)
    if (lent.data == data && lent.size == size) return;
  lent_.push_back({std::move(owner), data, size});
}

const FrontStream::Lent* FrontStream::lent_for(const char* data, size_t size) const {
  for (const Lent& lent : lent_)
    if (std::less_equal<const char*>()(lent.data, data) &&
        std::less_equal<const char*>()(data + size, lent.data + lent.size))
      return &lent;
  return nullptr;
}

PendingOutput FrontStream::take_pending() {
  // The queue's copies stay charged to the budget: the loop gives them back as they go.
  PendingOutput taken = std::move(pending_);
  pending_ = PendingOutput();
  return taken;
}

bool FrontStream::is_writable() const {
  if (failed_) return false;
  // A peer that has closed reads as end of file: not writable any more (event streams
  // end). Bytes waiting to be read are a next request, not an end.
  pollfd entry{socket_, POLLIN, 0};
  if (::poll(&entry, 1, 0) > 0) {
    char probe;
    const ssize_t n = ::recv(socket_, &probe, 1, MSG_PEEK | MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) return false;
  }
  return true;
}

ssize_t FrontStream::read(char* ptr, size_t size) {
  const size_t n = std::min(size, request_.size() - read_at_);
  std::memcpy(ptr, request_.data() + read_at_, n);
  read_at_ += n;
  return static_cast<ssize_t>(n);
}

ssize_t FrontStream::write(const char* ptr, size_t size) {
  if (failed_) return -1;
  if (drop_continue_ && std::string_view(ptr, size) == kContinue) {
    drop_continue_ = false;
    return static_cast<ssize_t>(size);
  }
  if (first_write_) {
    first_write_ = false;
    response_start_ = Clock::now();
  }
  written_ += size;
  // What earlier writes queued goes first, as far as the socket takes it now: a long
  // response (an event stream) must not wait for its end to send what it queued.
  if (!pending_.empty()) {
    const size_t copied = pending_.copied();
    if (!pending_.send_some(socket_, sent_)) {
      failed_ = true;
      return -1;
    }
    copy_budget_.fetch_add(static_cast<long long>(copied - pending_.copied()));
  }
  size_t offset = 0;
  if (pending_.empty()) {
    ssize_t n;
    do n = ::send(socket_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
    while (n < 0 && errno == EINTR);
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
      failed_ = true;
      return -1;
    }
    offset = n > 0 ? static_cast<size_t>(n) : 0;
    sent_ += offset;
  }
  const char* rest = ptr + offset;
  const size_t left = size - offset;
  if (left == 0) return static_cast<ssize_t>(size);
  if (const Lent* lent = lent_for(rest, left)) {
    pending_.push_reference(lent->owner, rest, left);
    return static_cast<ssize_t>(size);
  }
  const long long want = static_cast<long long>(left);
  if (pending_.copied() + left <= max_copied_bytes_ && copy_budget_.fetch_sub(want) >= want) {
    pending_.push_copy(rest, left);
    return static_cast<ssize_t>(size);
  }
  if (pending_.copied() + left <= max_copied_bytes_) copy_budget_.fetch_add(want);  // not taken
  return send_waiting(rest, left) ? static_cast<ssize_t>(size) : -1;
}

bool FrontStream::send_waiting(const char* data, size_t size) {
  PendingOutput rest;
  rest.push_reference(nullptr, data, size);
  for (PendingOutput* queue : {&pending_, &rest}) {
    Clock::time_point progress = Clock::now();
    while (!queue->empty()) {
      const size_t copied = queue->copied();
      const size_t before = sent_;
      if (!queue->send_some(socket_, sent_)) return !(failed_ = true);
      copy_budget_.fetch_add(static_cast<long long>(copied - queue->copied()));
      if (queue->empty()) break;
      const Clock::time_point now = Clock::now();
      if (sent_ > before) progress = now;
      const Clock::time_point until =
          std::min(progress + pace_.stall, pace_.deadline(response_start_, written_));
      if (now >= until) {
        timed_out_ = true;
        return !(failed_ = true);
      }
      pollfd entry{socket_, POLLOUT, 0};
      const auto wait = std::chrono::ceil<std::chrono::milliseconds>(until - now);
      ::poll(&entry, 1, static_cast<int>(std::min<long long>(wait.count(), 1000)));
    }
  }
  return true;
}

void FrontStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (::getpeername(socket_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    name_of(address, length, ip, port);
}

void FrontStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (::getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    name_of(address, length, ip, port);
}

void lend_response_bytes(std::shared_ptr<const void> owner, const char* data, size_t size) {
  if (FrontStream* stream = FrontStream::of_this_thread())
    stream->lend(std::move(owner), data, size);
}

}  // namespace spheremap::api
