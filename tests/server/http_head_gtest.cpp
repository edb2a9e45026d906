// The strict reading of a request's head (RFC 9110 / 9112): what clients send is accepted with
// its fields, and each way a head can be malformed or ambiguous is a refusal with its status.
#include "http/http_head.hpp"

#include <gtest/gtest.h>

using namespace compaction::server;

namespace {

RequestHead accepted(const std::string& head) {
  const auto r = parse_request_head(head);
  if (const auto* e = std::get_if<HeadError>(&r)) {
    ADD_FAILURE() << "refused " << e->status << " " << e->field << ": " << e->message;
    return {};
  }
  return std::get<RequestHead>(r);
}

HeadError refused(const std::string& head) {
  const auto r = parse_request_head(head);
  if (const auto* e = std::get_if<HeadError>(&r)) return *e;
  ADD_FAILURE() << "accepted: " << head;
  return {0, "", ""};
}

}  // namespace

TEST(HttpHead, ReadsWhatCurlSends) {
  const RequestHead h = accepted(
      "POST /api/v1/sweeps?x=1 HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nUser-Agent: curl/7.88\r\n"
      "Content-Type: application/json\r\nContent-Length: 42\r\nExpect: 100-continue\r\n");
  EXPECT_EQ(h.method, "POST");
  EXPECT_EQ(h.target, "/api/v1/sweeps?x=1");
  EXPECT_EQ(h.path, "/api/v1/sweeps");
  EXPECT_EQ(h.version, "HTTP/1.1");
  ASSERT_TRUE(h.content_length);
  EXPECT_EQ(*h.content_length, 42u);
  EXPECT_TRUE(h.expect_continue);
  EXPECT_TRUE(h.keep_alive);
  ASSERT_NE(h.find("content-type"), nullptr);
  EXPECT_EQ(*h.find("CONTENT-TYPE"), "application/json");
}

TEST(HttpHead, KeepAliveFollowsTheVersionAndConnection) {
  EXPECT_FALSE(accepted("GET / HTTP/1.1\r\nHost: a\r\nConnection: keep-alive, close\r\n").keep_alive);
  EXPECT_FALSE(accepted("GET / HTTP/1.0\r\n").keep_alive);
  EXPECT_TRUE(accepted("GET / HTTP/1.0\r\nConnection: Keep-Alive\r\n").keep_alive);
}

TEST(HttpHead, DecodesThePathAndRefusesNulOrBrokenEscapes) {
  EXPECT_EQ(accepted("GET /a%20b HTTP/1.1\r\nHost: a\r\n").path, "/a b");
  EXPECT_EQ(refused("GET /index.html%00.png HTTP/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET /a%zz HTTP/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET /a% HTTP/1.1\r\nHost: a\r\n").status, 400);
}

TEST(HttpHead, AnHttp11RequestNeedsExactlyOneHost) {
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nAccept: */*\r\n").field, "Host");
  const HeadError twice = refused("GET / HTTP/1.1\r\nHost: a\r\nHost: b\r\n");
  EXPECT_EQ(twice.status, 400);
  EXPECT_EQ(twice.field, "Host");
  accepted("GET / HTTP/1.0\r\n");  // HTTP/1.0 has no Host requirement
}

TEST(HttpHead, RefusesASingletonFieldTwice) {
  for (const char* name : {"Origin", "Authorization", "Content-Length", "Content-Type", "Cookie"}) {
    const HeadError e = refused(std::string("POST /x HTTP/1.1\r\nHost: a\r\n") + name + ": 1\r\n" +
                                name + ": 1\r\n");
    EXPECT_EQ(e.status, 400) << name;
    EXPECT_EQ(e.field, name) << name;
  }
  // A list field may come in several lines.
  accepted("GET / HTTP/1.1\r\nHost: a\r\nAccept: a\r\nAccept: b\r\n");
}

TEST(HttpHead, RefusesObsFoldLinesWithoutColonAndSpaceBeforeTheColon) {
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nHost: a\r\nX-A: 1\r\n  continued\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nHost: a\r\nno colon here\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nHost : a\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nHost: a\r\nX-A: a\x01b\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/1.1\r\nHost: a\nX-A: 1\r\n").status, 400);  // bare LF
}

TEST(HttpHead, RefusesMalformedRequestLines) {
  EXPECT_EQ(refused("GET  / HTTP/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/1.1 x\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET http://a/ HTTP/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTP/2.0\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET / HTTQ/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("G(T / HTTP/1.1\r\nHost: a\r\n").status, 400);
  EXPECT_EQ(refused("GET /" + std::string(kMaxTargetBytes, 'a') + " HTTP/1.1\r\nHost: a\r\n").status, 414);
}

TEST(HttpHead, ContentLengthIsDigitsAndNeverBesideTransferEncoding) {
  EXPECT_EQ(refused("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: -1\r\n").field, "Content-Length");
  EXPECT_EQ(refused("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1 2\r\n").field, "Content-Length");
  EXPECT_EQ(refused("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1\r\nTransfer-Encoding: chunked\r\n")
                .field,
            "Content-Length");
}

TEST(HttpHead, OnlyTheContinueExpectation) {
  EXPECT_EQ(refused("POST / HTTP/1.1\r\nHost: a\r\nExpect: magic\r\n").status, 417);
}

TEST(HttpHead, BoundsTheNumberOfFields) {
  std::string head = "GET / HTTP/1.1\r\nHost: a\r\n";
  for (std::size_t i = 0; i < kMaxHeadFields; ++i) head += "X-" + std::to_string(i) + ": 1\r\n";
  EXPECT_EQ(refused(head).status, 431);
}

TEST(HttpHead, FindsTheEndOfAHeadAcrossReads) {
  const std::string bytes = "\r\nGET / HTTP/1.1\r\nHost: a\r\n\r\nnext";
  EXPECT_EQ(leading_empty_lines(bytes), 2u);
  EXPECT_FALSE(find_head_end(bytes.substr(0, 28), 0));
  // Searching on from where the previous, shorter read ended finds an end that straddles it.
  EXPECT_EQ(find_head_end(bytes, 28), bytes.size() - 4);
  EXPECT_EQ(find_head_end(bytes, 0), bytes.size() - 4);
  accepted(bytes.substr(0, bytes.size() - 6));
}
