#include "server/serve.h"

#include <httplib.h>
#include <signal.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <thread>

#include "api/log.h"
#include "api/routes.h"
#include "server/service.h"

namespace spheremap::server {

namespace {

// Binds `http` to config.host and `port` (0: any free one); the port bound, or -1 after
// logging why not. A port in use is named plainly: it is the common mistake (a second
// serve, another program on 8080), and the bare strerror does not say which port.
int bind_port(httplib::Server& http, const ServerConfig& config, int port, const char* what) {
  errno = 0;
  const int bound = port == 0 ? http.bind_to_any_port(config.host)
                              : (http.bind_to_port(config.host, port) ? port : -1);
  if (bound >= 0) return bound;
  const int cause = errno;
  const std::string error =
      cause == EADDRINUSE
          ? "port " + std::to_string(port) + " on " + config.host + " is in use by another process"
      : cause != 0 ? std::string(std::strerror(cause))
                   : "cannot listen on " + config.host + ":" + std::to_string(port);
  log_event({{"event", "bind_failed"},
             {"listener", what},
             {"host", config.host},
             {"port", port},
             {"error", error}});
  return -1;
}

// Runs `server`'s accept loop on a thread of its own and returns once the loop runs.
// httplib's stop() does nothing to a server whose loop has not started (0.11.4: it acts
// only when is_running()), so a TERM that came between the bind and the loop's first
// step left the later join() waiting forever: a serve stopped right after it logged
// "listening" never ended on a loaded CI machine. Waiting here closes that window, and
// makes the "listening" line, logged after this, true.
std::thread start_accept_loop(api::GuardedServer& server) {
  auto returned = std::make_shared<std::atomic<bool>>(false);
  std::thread loop([&server, returned] {
    server.listen_after_bind();
    *returned = true;
  });
  while (!server.is_running() && !*returned)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return loop;
}

}  // namespace

int serve(const ServerConfig& config, Role role) {
  // Signals are taken by sigwait on this thread only: block them before any thread starts.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a client that hangs up must not end the process

  std::unique_ptr<Service> started;
  try {
    started = std::make_unique<Service>(config);
  } catch (const ConfigError& e) {
    log_event({{"event", "config_error"}, {"error", e.what()}});
    return 1;
  }
  Service& service = *started;
  const bool api = role == Role::kApi;
  api::GuardedServer http;
  if (api) api::install_api(http, service);
  // The health port, when asked for: probes answered by threads of their own, however
  // many clients hold the API's connections (slowloris, a full pool, a stuck proxy).
  api::GuardedServer health;
  int health_port = -1;
  if (config.health_port >= 0) {
    api::install_health(health, service);
    health_port = bind_port(health, config, config.health_port, "health");
  }
  const int port = api ? bind_port(http, config, config.port, "api") : 0;
  if (port < 0 || (config.health_port >= 0 && health_port < 0)) {
    service.drain(0);
    return 1;
  }
  std::thread health_listener;
  if (health_port >= 0) {
    health_listener = start_accept_loop(health);
    log_event({{"event", "health_listening"},
               {"host", config.host},
               {"port", health_port},
               {"url", "http://" + config.host + ":" + std::to_string(health_port)}});
  }
  std::thread listener;
  if (api) {
    listener = start_accept_loop(http);
    log_event({{"event", "listening"},
               {"host", config.host},
               {"port", port},
               {"url", "http://" + config.host + ":" + std::to_string(port)},
               {"config", config.to_json()}});
    // One line for a person beside the JSON log (which goes to stderr): where to look.
    std::string shown_host = config.host == "0.0.0.0" ? "127.0.0.1"
                             : config.host == "::"    ? "::1"
                                                      : config.host;
    if (shown_host.find(':') != std::string::npos) shown_host = "[" + shown_host + "]";
    std::printf("spheremap ready: open http://%s:%d/\n", shown_host.c_str(), port);
    std::fflush(stdout);
  } else {
    log_event({{"event", "worker_node"}, {"config", config.to_json()}});
  }

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
      service.stop_now();
    }
  });
  service.drain(config.shutdown_grace_seconds);
  drained = true;
  impatience.join();
  if (listener.joinable()) {
    http.stop();
    listener.join();
  }
  if (health_listener.joinable()) {
    health.stop();
    health_listener.join();
  }
  log_event({{"event", "stopped"}});
  return 0;
}

}  // namespace spheremap::server
