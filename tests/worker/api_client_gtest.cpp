// The worker's HTTP calls on the wire: a lease that follows a complete goes out on the
// complete's connection, and that connection is closed once the lease is answered, so a worker
// holds a connection (and a thread of the server) only between the two. The peer is an
// httplib server on loopback that records the client's port of every request.
#include "api_client.hpp"

#include <gtest/gtest.h>

#include <httplib.h>

#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

using compaction::worker::ApiClient;
using compaction::worker::Outcome;

namespace {

class RecordingServer {
 public:
  explicit RecordingServer(time_t keep_alive_seconds = 5) {
    server_.set_keep_alive_timeout(keep_alive_seconds);
    const auto record = [this](const httplib::Request& req, httplib::Response& res) {
      const std::lock_guard lock(mutex_);
      calls_.push_back({req.path, req.remote_port});
      res.set_content(R"({"ok": true})", "application/json");
    };
    server_.Post("/api/v1/leases", record);
    server_.Post(R"(/api/v1/jobs/\d+/(complete|heartbeat))", record);
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
    while (!server_.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ~RecordingServer() {
    server_.stop();
    thread_.join();
  }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  struct Call {
    std::string path;
    int client_port;
  };
  std::vector<Call> calls() {
    const std::lock_guard lock(mutex_);
    return calls_;
  }

 private:
  httplib::Server server_;
  int port_ = 0;
  std::thread thread_;
  std::mutex mutex_;
  std::vector<Call> calls_;
};

}  // namespace

TEST(ApiClientGtest, TheLeaseAfterACompleteSharesItsConnectionAndClosesIt) {
  RecordingServer server;
  ApiClient client(server.url(), "token");
  ASSERT_EQ(client.lease("w", "0").outcome, Outcome::ok);
  ASSERT_EQ(client.heartbeat(7, "t", 0.1).outcome, Outcome::ok);
  ASSERT_EQ(client.complete(7, "t", "{}", {{"frames.csv", "eps\n"}}).outcome, Outcome::ok);
  ASSERT_EQ(client.lease("w", "0").outcome, Outcome::ok);
  ASSERT_EQ(client.lease("w", "0").outcome, Outcome::ok);
  const auto calls = server.calls();
  ASSERT_EQ(calls.size(), 5u);
  EXPECT_EQ(calls[2].path, "/api/v1/jobs/7/complete");
  // The first lease and the heartbeat each open a connection of their own.
  EXPECT_NE(calls[0].client_port, calls[1].client_port);
  EXPECT_NE(calls[1].client_port, calls[2].client_port);
  // The complete's connection carries the next lease ...
  EXPECT_EQ(calls[2].client_port, calls[3].client_port);
  // ... and is closed after it: the lease after that one opens a new connection.
  EXPECT_NE(calls[3].client_port, calls[4].client_port);
}

TEST(ApiClientGtest, ALeaseOpensANewConnectionWhenTheServerClosedTheKeptOne) {
  RecordingServer server(/*keep_alive_seconds=*/1);
  ApiClient client(server.url(), "");
  ASSERT_EQ(client.complete(3, "t", "{}", {}).outcome, Outcome::ok);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // the server closes it
  ASSERT_EQ(client.lease("w", "0").outcome, Outcome::ok);
  const auto calls = server.calls();
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_NE(calls[0].client_port, calls[1].client_port);
}
