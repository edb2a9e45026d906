// The workers the server has heard from, each with the last time it asked for a lease or sent
// a heartbeat (the metrics' compaction_worker_last_seen_timestamp_seconds). Kept in memory: a
// restarted server knows a worker again at its next call. Bounded, so that workers named after
// batch jobs (a new name per Slurm task) cannot grow it: at most max_workers names, the one
// seen longest ago makes room for a new one, and a name unseen for forget_after_ms is dropped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace compaction::server {

class WorkersSeen {
 public:
  static constexpr std::size_t max_workers = 500;
  static constexpr std::int64_t forget_after_ms = 24 * 3600 * 1000;

  void seen(const std::string& worker, std::int64_t now_ms);
  // The workers seen within forget_after_ms of now, by name, with the time (ms) of their last call.
  std::vector<std::pair<std::string, std::int64_t>> list(std::int64_t now_ms);

 private:
  std::mutex mutex_;
  std::unordered_map<std::string, std::int64_t> last_;
};

}  // namespace compaction::server
