// The worker's HTTP calls to the server (the queue endpoints of docs/service.md). Each call
// answers what happened without throwing: transport failures are "unreachable", so the worker
// can wait and try again while a server restarts.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace httplib {
class Client;
}

namespace compaction::worker {

enum class Outcome {
  ok,
  empty,        // 204: nothing to lease
  lease_lost,   // 409: the lease is not live any more
  not_found,    // 404
  rejected,     // another 4xx: the request itself is wrong (details in message)
  unreachable,  // no answer or a 5xx: try again later
};

struct Reply {
  Outcome outcome = Outcome::unreachable;
  int status = 0;
  nlohmann::json body;  // parsed JSON body, null when none
  std::string message;  // error message for logs
};

struct UploadFile {
  std::string name;
  std::string data;
};

// Who asks for the next job with a result: the worker's name and the engine version it runs.
struct NextLease {
  std::string worker;
  std::string engine_version;
};

class ApiClient {
 public:
  ApiClient(std::string base_url, std::string token);
  ~ApiClient();

  // The next job: the one the last complete brought when it asked for one (its answer's
  // "next": a lease, or nothing to do now), otherwise a lease request of its own.
  Reply lease(const std::string& worker, const std::string& engine_version);
  // resumed: {"step", "eps"} of the checkpoint the run went on from, once (null: none).
  Reply heartbeat(std::int64_t job_id, const std::string& lease_token, double eps,
                  const nlohmann::json& resumed = nullptr);
  // The job's result. With `next`, the same request leases the worker's next job (one round
  // trip and one commit of the server instead of two), which the next lease() returns.
  Reply complete(std::int64_t job_id, const std::string& lease_token, const std::string& summary,
                 const std::vector<UploadFile>& files,
                 const std::optional<NextLease>& next = std::nullopt);
  // Gives back a job that a complete leased and no lease() took (the worker is stopping).
  void release_unclaimed();
  Reply fail(std::int64_t job_id, const std::string& lease_token, const std::string& reason,
             bool retryable);
  Reply release(std::int64_t job_id, const std::string& lease_token);
  // Stores the run's checkpoint (the file's bytes, where the run stood) under the live lease.
  Reply upload_checkpoint(std::int64_t job_id, const std::string& lease_token, std::int64_t step,
                          double eps, const std::string& bytes);
  // The job's stored checkpoint (the lease answer's "checkpoint"): its bytes into `bytes`.
  Reply download_checkpoint(std::int64_t job_id, std::string& bytes);

 private:
  Reply post_json(const std::string& path, const nlohmann::json& body);

  std::string base_url_;
  std::string token_;
  std::mutex next_mutex_;
  std::optional<Reply> next_;  // the lease a complete brought, until lease() takes it
};

}  // namespace compaction::worker
