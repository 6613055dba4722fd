// Where a request ends in the bytes received (api/request_head.h): the head at its blank
// line, the body after Content-Length bytes, found as the bytes arrive in any split, and
// the header and body caps refused on the way.
#include "api/request_head.h"

#include <gtest/gtest.h>

#include <string>

namespace spheremap::api {
namespace {

using State = RequestHeadScanner::State;

TEST(RequestHead, AHeadWithoutBodyIsWholeAtItsBlankLine) {
  ConnectionLimits limits;
  RequestHeadScanner scanner(limits);
  const std::string request = "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n";
  EXPECT_EQ(scanner.scan(request.substr(0, 20)), State::kIncomplete);
  EXPECT_EQ(scanner.scan(request), State::kComplete);
  EXPECT_EQ(scanner.request_bytes(), request.size());
  EXPECT_EQ(scanner.content_length(), 0u);
}

TEST(RequestHead, TheBodyIsWholeAfterContentLengthBytesWhateverTheSplit) {
  ConnectionLimits limits;
  const std::string head = "POST /v1/jobs HTTP/1.1\r\ncontent-LENGTH:  5\r\nHost: x\r\n\r\n";
  const std::string next = "GET / HTTP/1.1\r\n\r\n";
  const std::string all = head + "hello" + next;
  // Every split of the bytes into two arrivals finds the same end.
  for (size_t split = 0; split <= all.size(); ++split) {
    RequestHeadScanner scanner(limits);
    const State first = scanner.scan(std::string_view(all).substr(0, split));
    EXPECT_EQ(first, split >= head.size() + 5 ? State::kComplete : State::kIncomplete) << split;
    EXPECT_EQ(scanner.scan(all), State::kComplete);
    EXPECT_EQ(scanner.head_bytes(), head.size());
    EXPECT_EQ(scanner.request_bytes(), head.size() + 5);  // the next request is not this one's
  }
}

TEST(RequestHead, BareLineFeedsEndLinesToo) {
  ConnectionLimits limits;
  RequestHeadScanner scanner(limits);
  EXPECT_EQ(scanner.scan("GET / HTTP/1.1\nContent-Length: 2\n\nab"), State::kComplete);
  EXPECT_EQ(scanner.request_bytes(), 36u);
}

TEST(RequestHead, TooManyLinesOrBytesAre431BeforeTheHeadEnds) {
  ConnectionLimits limits;
  limits.max_header_count = 4;
  limits.max_header_bytes = 100;
  RequestHeadScanner lines(limits);
  EXPECT_EQ(lines.scan("GET / HTTP/1.1\r\na: 1\r\nb: 2\r\nc: 3\r\n\r\n"), State::kComplete);
  lines.reset();
  EXPECT_EQ(lines.scan("GET / HTTP/1.1\r\na: 1\r\nb: 2\r\nc: 3\r\nd: 4\r\n"), State::kRefused);
  EXPECT_EQ(lines.refusal().status, 431);
  EXPECT_EQ(lines.refusal().slug, "too_many_headers");
  RequestHeadScanner bytes(limits);
  EXPECT_EQ(bytes.scan("GET / HTTP/1.1\r\nX: " + std::string(100, 'v')), State::kRefused);
  EXPECT_EQ(bytes.refusal().slug, "headers_too_large");
}

TEST(RequestHead, ADeclaredBodyOverTheCapIs413AtTheHead) {
  ConnectionLimits limits;
  limits.max_body_bytes = 1000;
  RequestHeadScanner scanner(limits);
  EXPECT_EQ(scanner.scan("POST / HTTP/1.1\r\nContent-Length: 1001\r\n\r\n"), State::kRefused);
  EXPECT_EQ(scanner.refusal().status, 413);
  EXPECT_EQ(scanner.refusal().slug, "too_large");
  scanner.reset();
  EXPECT_EQ(scanner.scan("POST / HTTP/1.1\r\nContent-Length: 1000\r\n\r\n"), State::kIncomplete);
}

TEST(RequestHead, ChunkedBodiesAreNotWaitedForAndExpectIsSeen) {
  ConnectionLimits limits;
  RequestHeadScanner scanner(limits);
  EXPECT_EQ(scanner.scan("POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n"
                         "Expect: 100-continue\r\n\r\n5\r\nhello"),
            State::kComplete);
  EXPECT_TRUE(scanner.has_transfer_encoding());
  EXPECT_TRUE(scanner.expects_continue());
  EXPECT_EQ(scanner.content_length(), 0u);
}

TEST(RequestHead, TheFirstContentLengthCountsAsInCppHttplib) {
  ConnectionLimits limits;
  RequestHeadScanner scanner(limits);
  EXPECT_EQ(scanner.scan("POST / HTTP/1.1\r\nContent-Length: 3\r\nContent-Length: 9\r\n\r\nabc"),
            State::kComplete);
  EXPECT_EQ(scanner.content_length(), 3u);
}

}  // namespace
}  // namespace spheremap::api
