// Response bytes a client has not taken yet, queued in order: references to bytes that
// outlive the response (shared artifacts, lent by their handler) and copies of the rest.
// The event front (api/event_front.h) sends them as the socket accepts more, so a client
// that reads slowly or never holds a queue, not a thread.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <deque>
#include <memory>

namespace spheremap::api {

class PendingOutput {
 public:
  bool empty() const { return segments_.empty(); }
  size_t bytes() const { return bytes_; }    // queued, not sent
  size_t copied() const { return copied_; }  // of which copies this queue owns
  // Queues `size` bytes at `data`, which `owner` keeps valid (no copy).
  void push_reference(std::shared_ptr<const void> owner, const char* data, size_t size);
  // Queues a copy of `size` bytes at `data`.
  void push_copy(const char* data, size_t size);
  // Sends what `socket` takes without waiting; adds the bytes sent to `sent`. False on a
  // socket error (the peer is gone); true when the queue is empty or the socket is full.
  bool send_some(int socket, size_t& sent);

 private:
  struct Segment {
    std::shared_ptr<const void> owner;
    const char* data;
    size_t size;
    bool copy;
  };
  std::deque<Segment> segments_;
  size_t bytes_ = 0;
  size_t copied_ = 0;
};

}  // namespace spheremap::api
