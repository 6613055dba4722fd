// The real service on a loopback port, in the test's process: the same Service, routes
// and cpp-httplib server as `spheremap serve`, without the signal handling.
#pragma once

#include <httplib.h>

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

}  // namespace spheremap::testing
