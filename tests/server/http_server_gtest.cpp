// The HTTP server's connection rules (http/http_front.hpp, http/http_server.hpp) on a real
// socket: a handler that works longer than the pace rule's grace still answers (the answer's
// pace counts from its first byte), and a large answer keeps the pace for a client that reads.
#include "http/http_server.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

using namespace compaction::server;

namespace {

struct Served {
  HttpServer server;
  std::thread thread;
  int port = 0;

  explicit Served(ConnectionLimits limits) : server(limits) {}
  void start() {
    port = server.bind_to_any_port("127.0.0.1");
    ASSERT_GT(port, 0);
    thread = std::thread([this] { server.listen_after_bind(); });
    while (!server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ~Served() {
    server.stop();
    if (thread.joinable()) thread.join();
  }
};

}  // namespace

TEST(HttpServer, AHandlerThatWorksLongerThanTheGraceStillAnswers) {
  ConnectionLimits limits;
  limits.body_grace_seconds = 0.2;  // the pace rule's grace, far below the handler's work
  Served s(limits);
  s.server.Get("/slow", [](const httplib::Request&, httplib::Response& res) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    res.set_content(std::string(1 << 20, 'x'), "text/plain");
  });
  s.start();
  httplib::Client client("127.0.0.1", s.port);
  client.set_read_timeout(10, 0);
  const auto r = client.Get("/slow");
  ASSERT_TRUE(r) << "no answer: " << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->body.size(), 1u << 20);
}

// Answers are gzip or plain, never brotli (cpp-httplib 0.11 compresses brotli at about 1 MB/s):
// the front rewrites the request's Accept-Encoding to gzip when it takes gzip, else removes it.
TEST(HttpServer, AnswersAreCompressedWithGzipOrNotAtAll) {
  Served s(ConnectionLimits{});
  std::string seen;
  s.server.Get("/table", [&seen](const httplib::Request& req, httplib::Response& res) {
    seen = req.get_header_value("Accept-Encoding");
    res.set_content(std::string(1 << 20, 'x'), "text/csv");
  });
  s.start();
  httplib::Client client("127.0.0.1", s.port);
  client.set_read_timeout(10, 0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"gzip, deflate, br", "gzip"},  // a browser's
      {"br", ""},
      {"br;q=1.0, gzip;q=0.5", "gzip"},
      {"gzip;q=0, br", ""},
      {"*", "gzip"},
      {"identity", ""},
  };
  for (const auto& [asked, answered] : cases) {
    const auto r = client.Get("/table", {{"Accept-Encoding", asked}});
    ASSERT_TRUE(r) << asked;
    EXPECT_EQ(r->status, 200) << asked;
    EXPECT_EQ(r->get_header_value("Content-Encoding"), answered) << asked;
    EXPECT_EQ(seen, answered) << asked;
    EXPECT_EQ(r->body, std::string(1 << 20, 'x')) << asked;  // the client inflates gzip
  }
}
