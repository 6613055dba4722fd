// The real service on a loopback port, in the test's process: the same Service, routes
// and cpp-httplib server as `spheremap serve`, without the signal handling.
#pragma once

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <memory>
#include <thread>

#include "api/routes.h"
#include "server/service.h"

namespace spheremap::testing {

class TestServer {
 public:
  explicit TestServer(server::ServerConfig config) {
    config.host = "127.0.0.1";
    config.port = 0;
    service_ = std::make_unique<server::Service>(config);
    api::install_api(http_, *service_);
    port_ = http_.bind_to_any_port("127.0.0.1");
    listener_ = std::thread([this] { http_.listen_after_bind(); });
    while (!http_.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ~TestServer() {
    service_->drain(0);
    http_.stop();
    listener_.join();
  }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(std::chrono::seconds(600));
    return c;
  }
  server::Service& service() { return *service_; }
  int port() const { return port_; }

 private:
  std::unique_ptr<server::Service> service_;
  api::GuardedServer http_;
  int port_ = 0;
  std::thread listener_;
};

// A TCP connection to the test server from `source` (any 127.x.y.z address reaches it).
inline int connect_from(int port, const char* source) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  inet_pton(AF_INET, source, &local.sin_addr);
  if (bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) return close(fd), -1;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) return close(fd), -1;
  return fd;
}

}  // namespace spheremap::testing
