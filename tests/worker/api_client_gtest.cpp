// The worker's HTTP calls on the wire: a complete that asks for the next job sends the lease
// request with the result (form field next_lease) and the next lease() answers from what the
// complete brought, without a request of its own; a job leased that way and never taken is
// released. The peer is an httplib server on loopback that records every request and answers
// as compaction-server does.
#include "api_client.hpp"

#include <gtest/gtest.h>

#include <httplib.h>

#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

using compaction::worker::ApiClient;
using compaction::worker::NextLease;
using compaction::worker::Outcome;
using nlohmann::json;

namespace {

class RecordingServer {
 public:
  // next_job: what a complete that asks for the next job answers under "next" (null: none).
  explicit RecordingServer(json next_job) : next_job_(std::move(next_job)) {
    const auto record = [this](const httplib::Request& req, httplib::Response& res) {
      const std::lock_guard lock(mutex_);
      Call call{req.path, {}};
      if (req.has_file("next_lease")) call.next_lease = json::parse(req.get_file_value("next_lease").content);
      calls_.push_back(call);
      json answer = {{"job_id", 7}, {"lease_token", "t"}};
      if (req.has_file("next_lease")) answer["next"] = next_job_;
      res.set_content(answer.dump(), "application/json");
    };
    server_.Post("/api/v1/leases", record);
    server_.Post(R"(/api/v1/jobs/\d+/(complete|heartbeat|release))", record);
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
    json next_lease;  // the form field, null when absent
  };
  std::vector<Call> calls() {
    const std::lock_guard lock(mutex_);
    return calls_;
  }

 private:
  json next_job_;
  httplib::Server server_;
  int port_ = 0;
  std::thread thread_;
  std::mutex mutex_;
  std::vector<Call> calls_;
};

const json kNextJob = {{"job_id", 8}, {"lease_token", "u"}, {"scene", json::object()}};

}  // namespace

TEST(ApiClientGtest, ACompleteThatAsksForTheNextJobBringsItToTheNextLease) {
  RecordingServer server(kNextJob);
  ApiClient client(server.url(), "token");
  ASSERT_EQ(client.complete(7, "t", "{}", {{"frames.csv", "eps\n"}}, NextLease{"w", "0.2.1"}).outcome,
            Outcome::ok);
  const auto next = client.lease("w", "0.2.1");
  EXPECT_EQ(next.outcome, Outcome::ok);
  EXPECT_EQ(next.status, 200);
  EXPECT_EQ(next.body, kNextJob);
  ASSERT_EQ(client.lease("w", "0.2.1").outcome, Outcome::ok);  // a request of its own
  const auto calls = server.calls();
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls[0].path, "/api/v1/jobs/7/complete");
  EXPECT_EQ(calls[0].next_lease, (json{{"worker", "w"}, {"engine_version", "0.2.1"}}));
  EXPECT_EQ(calls[1].path, "/api/v1/leases");
}

TEST(ApiClientGtest, NoNextJobMakesTheNextLeaseEmptyWithoutARequest) {
  RecordingServer server(nullptr);
  ApiClient client(server.url(), "");
  ASSERT_EQ(client.complete(7, "t", "{}", {}, NextLease{"w", "0"}).outcome, Outcome::ok);
  const auto next = client.lease("w", "0");
  EXPECT_EQ(next.outcome, Outcome::empty);
  EXPECT_EQ(next.status, 204);
  EXPECT_EQ(server.calls().size(), 1u);
}

TEST(ApiClientGtest, ACompleteWithoutNextLeavesTheLeaseToARequest) {
  RecordingServer server(kNextJob);
  ApiClient client(server.url(), "");
  ASSERT_EQ(client.complete(7, "t", "{}", {}).outcome, Outcome::ok);
  ASSERT_EQ(client.lease("w", "0").outcome, Outcome::ok);
  const auto calls = server.calls();
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_TRUE(calls[0].next_lease.is_null());
  EXPECT_EQ(calls[1].path, "/api/v1/leases");
}

TEST(ApiClientGtest, AJobTheLastCompleteLeasedIsReleasedWhenNoLeaseTakesIt) {
  RecordingServer server(kNextJob);
  ApiClient client(server.url(), "");
  ASSERT_EQ(client.complete(7, "t", "{}", {}, NextLease{"w", "0"}).outcome, Outcome::ok);
  client.release_unclaimed();
  client.release_unclaimed();  // nothing left to give back
  const auto calls = server.calls();
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls[1].path, "/api/v1/jobs/8/release");
}
