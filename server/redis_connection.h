// A connection to Redis (Debian's hiredis, synchronous API) that owns its context and
// its replies, and says what went wrong as an exception.
//
// One connection serves one thread at a time (hiredis contexts are not thread-safe).
// A connection that failed (Redis restarted, the network dropped, a timeout) is broken
// for good: the next command() reconnects first, so that callers only ever retry.
#pragma once

#include <hiredis/hiredis.h>

#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace spheremap::server {

// Redis could not be reached or did not answer: the caller may retry later. A command
// Redis refused (a bug of ours, or a script error) is a std::runtime_error instead.
class RedisUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// redis://HOST[:PORT][/DB]; throws std::invalid_argument with what is wrong.
struct RedisAddress {
  std::string host = "127.0.0.1";
  int port = 6379;
  int db = 0;
  static RedisAddress parse(const std::string& url);
  std::string text() const;  // as given back in logs
};

// One reply, freed with the object. Integer, string (also status and error) or array.
class RedisReply {
 public:
  explicit RedisReply(redisReply* reply);  // takes ownership
  bool is_nil() const { return reply_->type == REDIS_REPLY_NIL; }
  long long integer() const;           // an integer reply, or a string holding one
  std::string text() const;            // a string or status reply ("" for nil)
  size_t size() const;                 // elements of an array reply (0 for nil)
  RedisReply element(size_t i) const;  // shares the whole reply: valid on its own

 private:
  explicit RedisReply(std::shared_ptr<redisReply> reply) : reply_(std::move(reply)) {}
  std::shared_ptr<redisReply> reply_;
};

class RedisConnection {
 public:
  // Connects lazily, on the first command; `timeout_seconds` bounds connecting and every
  // command (a blocking read asks for its own, longer, timeout).
  RedisConnection(RedisAddress address, double timeout_seconds = 2);
  RedisConnection(const RedisConnection&) = delete;
  RedisConnection& operator=(const RedisConnection&) = delete;

  // Sends one command (arguments are binary-safe) and returns its reply. Throws
  // RedisUnavailable when Redis cannot be reached (the connection is dropped and made
  // anew next time), std::runtime_error when Redis answers with an error.
  RedisReply command(const std::vector<std::string_view>& arguments);
  // The same, for a command that may block for up to `block_seconds` on the server.
  RedisReply blocking_command(const std::vector<std::string_view>& arguments, double block_seconds);
  // The same, bounded by `timeout_seconds` instead of the connection's own timeout: a
  // command that carries megabytes needs longer than one that carries an id.
  RedisReply command_within(const std::vector<std::string_view>& arguments, double timeout_seconds);

 private:
  void connect();
  void drop();
  RedisReply send(const std::vector<std::string_view>& arguments);

  const RedisAddress address_;
  const double timeout_seconds_;
  std::unique_ptr<redisContext, void (*)(redisContext*)> context_;
};

// Connections shared by the threads of one process (the HTTP threads): a thread takes one
// for a few commands and gives it back. At most `max_idle` are kept open between uses.
class RedisPool {
 public:
  explicit RedisPool(RedisAddress address, size_t max_idle = 8);
  const RedisAddress& address() const { return address_; }

  class Lease {
   public:
    Lease(RedisPool& pool, std::unique_ptr<RedisConnection> connection)
        : pool_(pool), connection_(std::move(connection)) {}
    ~Lease() { pool_.give_back(std::move(connection_)); }
    RedisConnection* operator->() { return connection_.get(); }
    RedisConnection& operator*() { return *connection_; }

   private:
    RedisPool& pool_;
    std::unique_ptr<RedisConnection> connection_;
  };
  Lease take();

 private:
  void give_back(std::unique_ptr<RedisConnection> connection);
  const RedisAddress address_;
  const size_t max_idle_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<RedisConnection>> idle_;
};

}  // namespace spheremap::server
