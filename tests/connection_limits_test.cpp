// The connection limits of the API port (api/guarded_server.h), on the real service over
// raw sockets: header and body deadlines however slowly a client trickles, header line
// and byte caps, connections per address (loopback 127.0.0.2 stands for a remote client:
// 127.0.0.1 is exempt), and pipelined requests all answered.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "tests/test_server.h"

namespace spheremap {
namespace {

using testing::connect_from;
using testing::TestServer;
using Clock = std::chrono::steady_clock;

server::ServerConfig limits_config() {
  server::ServerConfig config;
  config.workers = 1;
  config.threads_per_job = 1;
  config.http_threads = 8;
  config.header_timeout_seconds = 0.5;
  config.body_timeout_seconds = 0.5;
  config.worker_isolation = "thread";
  return config;
}

void send_text(int fd, const std::string& text) {
  EXPECT_EQ(send(fd, text.data(), text.size(), MSG_NOSIGNAL), static_cast<ssize_t>(text.size()));
}

// Everything the server sends until it closes the connection or `seconds` pass.
std::string read_all(int fd, double seconds = 5) {
  std::string answer;
  const Clock::time_point until =
      Clock::now() + std::chrono::milliseconds(static_cast<int>(seconds * 1000));
  char buffer[4096];
  while (Clock::now() < until) {
    pollfd entry{fd, POLLIN, 0};
    if (poll(&entry, 1, 50) <= 0) continue;
    const ssize_t got = recv(fd, buffer, sizeof buffer, 0);
    if (got <= 0) break;
    answer.append(buffer, static_cast<size_t>(got));
  }
  return answer;
}

std::string status_line(const std::string& answer) {
  return answer.substr(0, answer.find("\r\n"));
}

TEST(ConnectionLimits, HeadersTrickledPastTheDeadlineGet408) {
  TestServer server(limits_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  const Clock::time_point start = Clock::now();
  send_text(fd, "GET /healthz HTTP/1.1\r\nHost: x\r\n");
  // A header line every 100 ms: each read is quick, the whole never ends.
  std::string answer;
  for (int k = 0; k < 30 && answer.empty(); ++k) {
    send(fd, "X-a: b\r\n", 8, MSG_NOSIGNAL);
    answer = read_all(fd, 0.1);
  }
  if (answer.empty()) answer = read_all(fd, 1);
  close(fd);
  EXPECT_EQ(status_line(answer), "HTTP/1.1 408 Request Timeout");
  EXPECT_NE(answer.find("header_timeout"), std::string::npos);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 2.0);
  // Counted where operators look, once: as a rejection, not also as a response of the
  // library's own (it reports a refused request as a 400).
  auto client = server.client();
  const std::string metrics = client.Get("/metrics")->body;
  EXPECT_NE(metrics.find("spheremap_rejections_total{reason=\"header_timeout\"} 1"),
            std::string::npos);
  EXPECT_EQ(metrics.find("spheremap_http_responses_total{code=\"400\"}"), std::string::npos);
}

TEST(ConnectionLimits, ARequestRefusedBeforeRoutingIsLoggedWithItsPeerAndDuration) {
  TestServer server(limits_config());
  ::testing::internal::CaptureStderr();
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd, "NONSENSE\r\n\r\n");
  const std::string answer = read_all(fd, 2);
  close(fd);
  // Read until the server closes (after logging) or 2 s pass: the line is written.
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(status_line(answer), "HTTP/1.1 400 Bad Request");
  const size_t at = log.find("\"event\":\"request\"");
  ASSERT_NE(at, std::string::npos) << log;
  const std::string line = log.substr(at, log.find('\n', at) - at);
  EXPECT_NE(line.find("\"remote\":\"127.0.0.2\""), std::string::npos) << line;
  const size_t ms = line.find("\"ms\":");
  ASSERT_NE(ms, std::string::npos) << line;
  EXPECT_LT(std::stod(line.substr(ms + 5)), 10'000.0) << line;
}

TEST(ConnectionLimits, BodyTrickledPastTheDeadlineGets408) {
  TestServer server(limits_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
            "Content-Length: 1000\r\n\r\nglTF");
  std::string answer;
  for (int k = 0; k < 30 && answer.empty(); ++k) {
    send(fd, "x", 1, MSG_NOSIGNAL);
    answer = read_all(fd, 0.1);
  }
  close(fd);
  EXPECT_EQ(status_line(answer), "HTTP/1.1 408 Request Timeout");
  EXPECT_NE(answer.find("body_timeout"), std::string::npos);
}

TEST(ConnectionLimits, TooManyOrTooLargeHeadersGet431) {
  server::ServerConfig config = limits_config();
  config.header_timeout_seconds = 10;
  TestServer server(config);
  std::string many = "GET /healthz HTTP/1.1\r\nHost: x\r\n";
  for (int k = 0; k < 200; ++k) many += "X-" + std::to_string(k) + ": v\r\n";
  int fd = connect_from(server.port(), "127.0.0.1");
  send_text(fd, many + "\r\n");
  std::string answer = read_all(fd);
  close(fd);
  EXPECT_EQ(status_line(answer), "HTTP/1.1 431 Request Header Fields Too Large");
  EXPECT_NE(answer.find("too_many_headers"), std::string::npos);

  std::string large = "GET /healthz HTTP/1.1\r\nHost: x\r\n";
  for (int k = 0; k < 8; ++k)
    large += "X-" + std::to_string(k) + ": " + std::string(6000, 'v') + "\r\n";
  fd = connect_from(server.port(), "127.0.0.1");
  send_text(fd, large + "\r\n");
  answer = read_all(fd);
  close(fd);
  EXPECT_EQ(status_line(answer), "HTTP/1.1 431 Request Header Fields Too Large");
  EXPECT_NE(answer.find("headers_too_large"), std::string::npos);
}

TEST(ConnectionLimits, PipelinedRequestsAreAllAnswered) {
  TestServer server(limits_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\nGET /v1/openapi.yaml HTTP/1.1\r\nHost: "
            "x\r\n\r\nGET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  const std::string answer = read_all(fd);
  close(fd);
  size_t answers = 0;
  for (size_t at = answer.find("HTTP/1.1 200 OK"); at != std::string::npos;
       at = answer.find("HTTP/1.1 200 OK", at + 1))
    ++answers;
  EXPECT_EQ(answers, 3u) << answer.substr(0, 300);
  EXPECT_NE(answer.find("openapi: "), std::string::npos);
}

TEST(ConnectionLimits, OneAddressHoldsAtMostItsShareOfConnections) {
  server::ServerConfig config = limits_config();
  config.header_timeout_seconds = 30;
  config.max_connections_per_address = 2;
  config.trusted_proxies = "127.0.0.3";
  TestServer server(config);
  // Two connections from one client, each half-way through its headers, hold two threads.
  int held[2];
  for (int& fd : held) {
    fd = connect_from(server.port(), "127.0.0.2");
    send_text(fd, "GET /healthz HTTP/1.1\r\n");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  int third = connect_from(server.port(), "127.0.0.2");
  send_text(third, "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
  const std::string refused = read_all(third);
  close(third);
  EXPECT_EQ(status_line(refused), "HTTP/1.1 429 Too Many Requests");
  EXPECT_NE(refused.find("too_many_connections"), std::string::npos);
  EXPECT_NE(refused.find("Retry-After: 1"), std::string::npos);
  // Other addresses are served meanwhile: loopback and a trusted proxy are not capped
  // (three proxy connections held at once).
  int proxied[3];
  for (int& fd : proxied) {
    fd = connect_from(server.port(), "127.0.0.3");
    send_text(fd, "GET /healthz HTTP/1.1\r\n");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  for (int fd : proxied) {
    send_text(fd, "Host: x\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(status_line(read_all(fd)), "HTTP/1.1 200 OK");
    close(fd);
  }
  for (const char* other : {"127.0.0.1", "127.0.0.4"}) {
    const int fd = connect_from(server.port(), other);
    send_text(fd, "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    EXPECT_EQ(status_line(read_all(fd)), "HTTP/1.1 200 OK") << other;
    close(fd);
  }
  // The held ones end; the client's connections count again from zero.
  for (int fd : held) close(fd);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const int again = connect_from(server.port(), "127.0.0.2");
  send_text(again, "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(status_line(read_all(again)), "HTTP/1.1 200 OK");
  close(again);
}

}  // namespace
}  // namespace spheremap
