#include "server/redis_connection.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace spheremap::server {
namespace {

timeval to_timeval(double seconds) {
  const double whole = std::floor(seconds);
  return {static_cast<time_t>(whole), static_cast<suseconds_t>((seconds - whole) * 1e6)};
}

int parse_number(std::string_view text, const char* what, int min, int max) {
  int value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < min || value > max)
    throw std::invalid_argument(std::string("redis URL: bad ") + what + " '" +
                                std::string(text.substr(0, 16)) + "'");
  return value;
}

}  // namespace

RedisAddress RedisAddress::parse(const std::string& url) {
  const std::string_view scheme = "redis://";
  if (!url.starts_with(scheme))
    throw std::invalid_argument("queue URL must be memory:// or redis://HOST[:PORT][/DB]");
  std::string_view rest = std::string_view(url).substr(scheme.size());
  RedisAddress address;
  if (const size_t slash = rest.find('/'); slash != std::string_view::npos) {
    if (slash + 1 < rest.size()) address.db = parse_number(rest.substr(slash + 1), "db", 0, 1023);
    rest = rest.substr(0, slash);
  }
  if (const size_t colon = rest.rfind(':'); colon != std::string_view::npos) {
    address.port = parse_number(rest.substr(colon + 1), "port", 1, 65535);
    rest = rest.substr(0, colon);
  }
  if (rest.find('@') != std::string_view::npos)
    throw std::invalid_argument("redis URL: credentials are not supported");
  if (!rest.empty()) address.host = std::string(rest);
  return address;
}

std::string RedisAddress::text() const {
  return "redis://" + host + ":" + std::to_string(port) + "/" + std::to_string(db);
}

RedisReply::RedisReply(redisReply* reply)
    : reply_(reply, [](redisReply* r) { freeReplyObject(r); }) {}

long long RedisReply::integer() const {
  if (reply_->type == REDIS_REPLY_INTEGER) return reply_->integer;
  long long value = 0;
  if (reply_->type == REDIS_REPLY_STRING || reply_->type == REDIS_REPLY_STATUS)
    std::from_chars(reply_->str, reply_->str + reply_->len, value);
  return value;
}

std::string RedisReply::text() const {
  if (reply_->type == REDIS_REPLY_STRING || reply_->type == REDIS_REPLY_STATUS ||
      reply_->type == REDIS_REPLY_ERROR)
    return std::string(reply_->str, reply_->len);
  if (reply_->type == REDIS_REPLY_INTEGER) return std::to_string(reply_->integer);
  return "";
}

size_t RedisReply::size() const {
  return reply_->type == REDIS_REPLY_ARRAY ? reply_->elements : 0;
}

RedisReply RedisReply::element(size_t i) const {
  if (i >= size()) throw std::out_of_range("redis reply has no element " + std::to_string(i));
  return RedisReply(std::shared_ptr<redisReply>(reply_, reply_->element[i]));
}

RedisConnection::RedisConnection(RedisAddress address, double timeout_seconds)
    : address_(std::move(address)),
      timeout_seconds_(timeout_seconds),
      context_(nullptr, redisFree) {}

void RedisConnection::drop() {
  context_.reset();
}

void RedisConnection::connect() {
  const timeval timeout = to_timeval(timeout_seconds_);
  context_.reset(redisConnectWithTimeout(address_.host.c_str(), address_.port, timeout));
  if (!context_ || context_->err) {
    const std::string why = context_ ? context_->errstr : "out of memory";
    drop();
    throw RedisUnavailable("cannot connect to " + address_.text() + ": " + why);
  }
  redisSetTimeout(context_.get(), timeout);
  if (address_.db != 0) send({"SELECT", std::to_string(address_.db)});
}

RedisReply RedisConnection::send(const std::vector<std::string_view>& arguments) {
  std::vector<const char*> argv;
  std::vector<size_t> lengths;
  for (std::string_view a : arguments) argv.push_back(a.data()), lengths.push_back(a.size());
  auto* reply = static_cast<redisReply*>(
      redisCommandArgv(context_.get(), static_cast<int>(argv.size()), argv.data(), lengths.data()));
  if (!reply) {
    const std::string why = context_->errstr;
    drop();
    throw RedisUnavailable("redis " + address_.text() + ": " + why);
  }
  RedisReply owned(reply);
  if (reply->type == REDIS_REPLY_ERROR) {
    const std::string text = owned.text();
    // A Redis that is loading its data, running a long script or is read-only answers
    // soon; say "try again". "BUSY " with its space: BUSYGROUP (a consumer group that
    // exists) and BUSYKEY are answers about the command, not about Redis.
    if (text.starts_with("LOADING") || text.starts_with("BUSY ") || text.starts_with("READONLY") ||
        text.starts_with("MASTERDOWN"))
      throw RedisUnavailable("redis " + address_.text() + ": " + text);
    throw std::runtime_error("redis " + std::string(arguments.front()) + ": " + text);
  }
  return owned;
}

RedisReply RedisConnection::command(const std::vector<std::string_view>& arguments) {
  if (!context_) connect();
  return send(arguments);
}

RedisReply RedisConnection::blocking_command(const std::vector<std::string_view>& arguments,
                                             double block_seconds) {
  return command_within(arguments, block_seconds + timeout_seconds_);
}

RedisReply RedisConnection::command_within(const std::vector<std::string_view>& arguments,
                                           double timeout_seconds) {
  if (!context_) connect();
  redisSetTimeout(context_.get(), to_timeval(timeout_seconds));
  auto restore = [&] {
    if (context_) redisSetTimeout(context_.get(), to_timeval(timeout_seconds_));
  };
  try {
    RedisReply reply = send(arguments);
    restore();
    return reply;
  } catch (...) {
    restore();
    throw;
  }
}

RedisPool::RedisPool(RedisAddress address, size_t max_idle)
    : address_(std::move(address)), max_idle_(max_idle) {}

RedisPool::Lease RedisPool::take() {
  std::unique_ptr<RedisConnection> connection;
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      connection = std::move(idle_.back());
      idle_.pop_back();
    }
  }
  if (!connection) connection = std::make_unique<RedisConnection>(address_);
  return Lease(*this, std::move(connection));
}

void RedisPool::give_back(std::unique_ptr<RedisConnection> connection) {
  std::lock_guard lock(mutex_);
  if (connection && idle_.size() < max_idle_) idle_.push_back(std::move(connection));
}

}  // namespace spheremap::server
