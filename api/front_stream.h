// One whole request as the event front (api/event_front.h) hands it to a pool thread:
// cpp-httplib reads it from memory (head and body are already here) and writes its
// answer through this stream. A write goes to the socket at once if the socket takes
// it; what it does not take is queued (PendingOutput) and sent later by the event loop,
// so the thread is free when the handler returns, however slowly the client reads.
// Queued bytes are references for bytes lent by the handler (lend_response_bytes: the
// shared artifacts of downloads) and copies for the rest, up to a cap; beyond the cap
// the thread sends them itself, within the response deadline.
//
// The response deadline: no progress for `stall`, or less than `min_bytes_per_second`
// on average after `stall` (the same rule the event loop applies to the queue).
#pragma once

#include <httplib.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "api/pending_output.h"
#include "api/served_connection.h"

namespace spheremap::api {

struct ResponsePace {
  ServedConnection::Clock::duration stall = std::chrono::seconds(30);
  double min_bytes_per_second = 16 << 10;
  // Deadline for `bytes` of a response started at `start`.
  ServedConnection::Clock::time_point deadline(ServedConnection::Clock::time_point start,
                                               size_t bytes) const;
};

class FrontStream final : public httplib::Stream, public ServedConnection {
 public:
  // `request` is the whole request (head and body); `copy_budget` the bytes of copies all
  // connections' queues may hold together (shared, updated here), of which this one
  // queues at most `max_copied_bytes`. `continue_sent`: the front has already answered
  // "100 Continue", so the library's own is dropped.
  FrontStream(socket_t socket, std::string request, const std::string& peer_address,
              Clock::time_point request_start, const ResponsePace& pace, size_t max_copied_bytes,
              std::atomic<long long>& copy_budget, bool continue_sent);
  ~FrontStream() override;

  // The stream serving this thread's request (nullptr elsewhere).
  static FrontStream* of_this_thread();
  // Marks this stream as serving the calling thread (until the stream ends).
  void bind_to_this_thread();

  // [data, data + size) stays valid while `owner` lives: queued as a reference.
  void lend(std::shared_ptr<const void> owner, const char* data, size_t size);
  // The bytes the socket has not taken yet, for the event loop (the stream is done).
  PendingOutput take_pending();
  // A write failed or ran past its deadline: the connection must close.
  bool failed() const { return failed_; }
  // ...because the client did not take it within the response deadline.
  bool timed_out() const { return timed_out_; }
  size_t bytes_written() const { return written_; }

  bool is_readable() const override { return read_at_ < request_.size(); }
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return socket_; }

  Clock::time_point request_start() const override { return request_start_; }
  const std::string& peer_address() const override { return peer_address_; }
  bool refused() const override { return false; }

 private:
  struct Lent {
    std::shared_ptr<const void> owner;
    const char* data;
    size_t size;
  };
  const Lent* lent_for(const char* data, size_t size) const;
  // Sends the queue and then [data, data + size) on this thread, waiting for the socket
  // up to the response deadline; false (failed) past it or on a socket error.
  bool send_waiting(const char* data, size_t size);

  socket_t socket_;
  std::string request_;
  size_t read_at_ = 0;
  std::string peer_address_;
  Clock::time_point request_start_;
  ResponsePace pace_;
  size_t max_copied_bytes_;
  std::atomic<long long>& copy_budget_;
  bool drop_continue_;
  bool failed_ = false;
  bool timed_out_ = false;
  bool first_write_ = true;
  Clock::time_point response_start_{};
  size_t written_ = 0;  // handed to the socket or the queue
  size_t sent_ = 0;     // taken by the socket
  PendingOutput pending_;
  std::vector<Lent> lent_;
};

// Lends the response bytes [data, data + size), kept valid by `owner`, to the stream
// serving this thread, if it is a FrontStream (else nothing): its writes of them queue a
// reference instead of waiting for the client. For handlers streaming shared bytes.
void lend_response_bytes(std::shared_ptr<const void> owner, const char* data, size_t size);

}  // namespace spheremap::api
