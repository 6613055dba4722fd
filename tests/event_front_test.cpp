// The API port's event front (api/event_front.h) on the real service over raw sockets:
// connections held without threads while requests arrive, keep-alive and pipelined
// requests (with bodies) answered in order, Expect: 100-continue answered once, chunked
// bodies refused as before, the caps on held bytes and connections, and responses that
// a client never reads ended (and logged) without holding a thread.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "core/io/glb_writer.h"
#include "tests/mesh_generators.h"
#include "tests/test_server.h"

namespace spheremap {
namespace {

using nlohmann::json;
using testing::connect_from;
using testing::TestServer;
using Clock = std::chrono::steady_clock;

server::ServerConfig front_config() {
  server::ServerConfig config;
  config.workers = 1;
  config.threads_per_job = 1;
  config.http_threads = 2;
  config.max_connections_per_address = 0;
  config.worker_isolation = "thread";
  return config;
}

void send_text(int fd, const std::string& text) {
  EXPECT_EQ(send(fd, text.data(), text.size(), MSG_NOSIGNAL), static_cast<ssize_t>(text.size()));
}

// What the server sends until it closes, `until` is in it, or `seconds` pass.
std::string read_until(int fd, const std::string& until = "", double seconds = 10) {
  std::string answer;
  const Clock::time_point end =
      Clock::now() + std::chrono::milliseconds(static_cast<int>(seconds * 1000));
  char buffer[4096];
  while (Clock::now() < end && (until.empty() || answer.find(until) == std::string::npos)) {
    pollfd entry{fd, POLLIN, 0};
    if (poll(&entry, 1, 50) <= 0) continue;
    const ssize_t got = recv(fd, buffer, sizeof buffer, 0);
    if (got <= 0) break;
    answer.append(buffer, static_cast<size_t>(got));
  }
  return answer;
}

size_t count_of(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

constexpr const char* kHealthz = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
constexpr const char* kHealthBody = "\"status\": \"ok\"\n}";

// 2 threads, 64 connections half-way through their headers: every one is held (each is
// answered once it ends its headers), and a probe from elsewhere is answered meanwhile.
// A thread per connection served 2 of them and left the probe waiting.
TEST(EventFront, HoldsFarMoreSlowConnectionsThanThreads) {
  TestServer server(front_config());
  std::vector<int> held;
  for (int k = 0; k < 64; ++k) {
    held.push_back(connect_from(server.port(), "127.0.0.2"));
    send_text(held.back(), "GET /healthz HTTP/1.1\r\nHost: x\r\n");
  }
  const int probe = connect_from(server.port(), "127.0.0.1");
  send_text(probe, kHealthz);
  EXPECT_NE(read_until(probe, kHealthBody).find("HTTP/1.1 200 OK"), std::string::npos);
  close(probe);
  size_t answered = 0;
  for (int fd : held) {
    send_text(fd, "Connection: close\r\n\r\n");
    answered += read_until(fd).starts_with("HTTP/1.1 200 OK") ? 1 : 0;
    close(fd);
  }
  EXPECT_EQ(answered, held.size());
}

TEST(EventFront, KeepAliveCarriesOneRequestAfterAnother) {
  TestServer server(front_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  for (int k = 0; k < 3; ++k) {
    send_text(fd, kHealthz);
    const std::string answer = read_until(fd, kHealthBody);
    EXPECT_TRUE(answer.starts_with("HTTP/1.1 200 OK")) << k << answer;
    EXPECT_EQ(count_of(answer, "HTTP/1.1"), 1u) << k;
  }
  close(fd);
}

// A request with a body and the one after it in one send: both answered, in order.
TEST(EventFront, PipelinedRequestsWithBodiesAreAnsweredInOrder) {
  TestServer server(front_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
            "Content-Length: 4\r\n\r\nnopeGET /healthz HTTP/1.1\r\nHost: x\r\n"
            "Connection: close\r\n\r\n");
  const std::string answer = read_until(fd);
  close(fd);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 4")) << answer.substr(0, 200);
  const size_t second = answer.find("HTTP/1.1 200 OK");
  ASSERT_NE(second, std::string::npos) << answer;
  EXPECT_EQ(count_of(answer, "HTTP/1.1 "), 2u);
}

TEST(EventFront, ExpectContinueIsAnsweredOnce) {
  TestServer server(front_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
            "Expect: 100-continue\r\nContent-Length: 4\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(read_until(fd, "\r\n\r\n"), "HTTP/1.1 100 Continue\r\n\r\n");
  send_text(fd, "nope");
  const std::string answer = read_until(fd);
  close(fd);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 4")) << answer.substr(0, 200);
  EXPECT_EQ(answer.find("100 Continue"), std::string::npos);
}

// As cpp-httplib with the service's routes answered before: 411, and the chunks that
// follow are not taken for a request.
TEST(EventFront, ChunkedBodiesAre411AndTheConnectionCloses) {
  TestServer server(front_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
            "4\r\nGET \r\n0\r\n\r\n");
  const std::string answer = read_until(fd);
  close(fd);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 411 Length Required")) << answer.substr(0, 200);
  EXPECT_EQ(count_of(answer, "HTTP/1.1 "), 1u);
}

// What the service refuses before reading a body (here a compressed one) is refused at
// the head, as before the front: the client need not send the body first.
TEST(EventFront, ARequestRefusedBeforeItsBodyIsAnsweredAtItsHead) {
  TestServer server(front_config());
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
            "Content-Encoding: gzip\r\nContent-Length: 1000000\r\n\r\n");
  const std::string answer = read_until(fd);
  close(fd);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 415 Unsupported Media Type")) << answer;
  EXPECT_NE(answer.find("unsupported_content_encoding"), std::string::npos);
  EXPECT_NE(answer.find("X-Content-Type-Options: nosniff"), std::string::npos);  // post-routing
}

TEST(EventFront, RequestBytesBeyondTheBufferAre503) {
  server::ServerConfig config = front_config();
  config.request_buffer_bytes = 64 << 10;
  TestServer server(config);
  const int fd = connect_from(server.port(), "127.0.0.2");
  send_text(fd,
            "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
            "Content-Length: 200000\r\n\r\n");
  const std::string body(100000, 'x');
  (void)!send(fd, body.data(), body.size(), MSG_NOSIGNAL);
  const std::string answer = read_until(fd);
  close(fd);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 503 Service Unavailable")) << answer.substr(0, 200);
  EXPECT_NE(answer.find("request_buffer_full"), std::string::npos);
}

TEST(EventFront, ConnectionsBeyondMaxConnectionsAre503) {
  server::ServerConfig config = front_config();
  config.max_connections = 16;
  TestServer server(config);
  std::vector<int> held;
  for (int k = 0; k < 16; ++k) {
    held.push_back(connect_from(server.port(), "127.0.0.1"));
    send_text(held.back(), "GET /healthz HTTP/1.1\r\n");
  }
  const int extra = connect_from(server.port(), "127.0.0.1");
  const std::string answer = read_until(extra);
  close(extra);
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 503 Service Unavailable")) << answer.substr(0, 200);
  for (int fd : held) close(fd);
}

// 6 clients that GET a 32 MB artifact and never read, with 2 threads: other requests
// are answered meanwhile (the unsent bytes wait in the event loop, by reference), and
// each download ends at its deadline (read_timeout_seconds without progress), logged.
TEST(EventFront, DownloadsNobodyReadsHoldNoThreadAndEnd) {
  server::ServerConfig config = front_config();
  config.worker_isolation = "process";
  config.worker_executable = SPHEREMAP_BINARY;
  config.read_timeout_seconds = 1;
  TestServer server(config);
  auto client = server.client();
  GlbMesh glb;
  const PolygonMesh mesh = testing::icosphere(1);
  glb.positions = mesh.positions;
  glb.triangles = fan_triangulate(mesh).triangles;
  auto submitted = client.Post("/v1/jobs", format_glb(glb), "model/gltf-binary");
  ASSERT_EQ(submitted->status, 202) << submitted->body;
  const std::string id = json::parse(submitted->body)["id"];
  for (int i = 0; i < 6000; ++i) {
    const json job = json::parse(client.Get(("/v1/jobs/" + id).c_str())->body);
    if (job["status"] != "queued" && job["status"] != "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  {
    const std::shared_ptr<api::Job> job = server.service().queue().find(id).job;
    ASSERT_TRUE(job);
    std::lock_guard lock(job->mutex);
    job->artifacts.push_back(api::make_artifact("large.bin", "application/octet-stream",
                                                std::string(size_t{32} << 20, 'x')));
  }
  ::testing::internal::CaptureStderr();
  std::vector<int> readers;
  for (int k = 0; k < 6; ++k) {
    const int fd = connect_from(server.port(), "127.0.0.2");
    int small = 4096;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    send_text(fd, "GET /v1/jobs/" + id + "/artifacts/large.bin HTTP/1.1\r\nHost: x\r\n\r\n");
    readers.push_back(fd);
  }
  for (const char* other : {"127.0.0.1", "127.0.0.3"}) {
    const int fd = connect_from(server.port(), other);
    send_text(fd, kHealthz);
    EXPECT_NE(read_until(fd, kHealthBody).find("HTTP/1.1 200 OK"), std::string::npos) << other;
    close(fd);
  }
  // Each reader's connection is reset at its deadline: seen in the socket's state, without
  // reading (a reader that read would be served). The log is read once at the end (lines
  // written between two captures would be lost: under CI's load 3 of 6 were).
  const auto reset = [](int fd) {
    tcp_info info{};
    socklen_t size = sizeof info;
    return getsockopt(fd, IPPROTO_TCP, TCP_INFO, &info, &size) == 0 && info.tcpi_state == TCP_CLOSE;
  };
  for (int k = 0; k < 600; ++k) {
    size_t ended = 0;
    for (int fd : readers) ended += reset(fd);
    if (ended == readers.size()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(count_of(log, "\"event\":\"response_abandoned\""), 6u) << log;
  // Each was closed: what a reader gets is less than the artifact, then the end.
  for (int fd : readers) {
    size_t got = 0;
    char buffer[65536];
    for (ssize_t n; (n = recv(fd, buffer, sizeof buffer, 0)) > 0;) got += static_cast<size_t>(n);
    EXPECT_LT(got, size_t{32} << 20);
    close(fd);
  }
}

}  // namespace
}  // namespace spheremap
