#include "server/serve.h"

#include <httplib.h>
#include <signal.h>

#include <atomic>
#include <cstring>
#include <ctime>
#include <thread>

#include "api/routes.h"
#include "server/log.h"
#include "server/service.h"

namespace spheremap::server {

int serve(const ServerConfig& config) {
  // Signals are taken by sigwait on this thread only: block them before any thread starts.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not end the process

  Service service(config);
  httplib::Server http;
  api::install_api(http, service);
  const int port = config.port == 0
                       ? http.bind_to_any_port(config.host)
                       : (http.bind_to_port(config.host, config.port) ? config.port : -1);
  if (port < 0) {
    log_event({{"event", "bind_failed"},
               {"host", config.host},
               {"port", config.port},
               {"error", std::strerror(errno)}});
    service.drain(0);
    return 1;
  }
  log_event({{"event", "listening"},
             {"host", config.host},
             {"port", port},
             {"url", "http://" + config.host + ":" + std::to_string(port)},
             {"config", config.to_json()}});
  std::thread listener([&http] { http.listen_after_bind(); });

  int received = 0;
  sigwait(&stop_signals, &received);
  log_event({{"event", "signal"}, {"signal", received == SIGTERM ? "SIGTERM" : "SIGINT"}});
  // A second signal during the grace period means "now": every job is cancelled at once
  // (an operator pressing Ctrl-C twice, or an orchestrator's second TERM).
  std::atomic<bool> drained{false};
  std::thread impatience([&] {
    const timespec tick{0, 100'000'000};
    while (!drained) {
      int again = sigtimedwait(&stop_signals, nullptr, &tick);
      if (again < 0) continue;
      log_event({{"event", "signal"},
                 {"signal", again == SIGTERM ? "SIGTERM" : "SIGINT"},
                 {"action", "cancelling every job now"}});
      service.store().cancel_all("the server was told to stop at once (a second signal)");
    }
  });
  service.drain(config.shutdown_grace_seconds);
  drained = true;
  impatience.join();
  http.stop();
  listener.join();
  log_event({{"event", "stopped"}});
  return 0;
}

}  // namespace spheremap::server
