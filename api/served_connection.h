// What the request logger knows of the connection a request came on, whichever layer
// serves it (GuardedStream on a thread per connection, FrontStream from the event front):
// requests cpp-httplib gives up on before routing carry neither a start time nor a
// remote address of their own.
#pragma once

#include <chrono>
#include <string>

namespace spheremap::api {

class ServedConnection {
 public:
  using Clock = std::chrono::steady_clock;
  virtual ~ServedConnection() = default;
  // When the current request's first bytes were there.
  virtual Clock::time_point request_start() const = 0;
  // The peer's numeric address ("" if the socket has none).
  virtual const std::string& peer_address() const = 0;
  // A connection limit was broken and answered: no response of the library's counts.
  virtual bool refused() const = 0;
};

}  // namespace spheremap::api
