#include "routes/workers_seen.hpp"

#include <algorithm>

namespace compaction::server {

void WorkersSeen::seen(const std::string& worker, std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  if (last_.size() >= max_workers && !last_.count(worker)) {
    last_.erase(std::min_element(last_.begin(), last_.end(), [](const auto& a, const auto& b) {
      return a.second < b.second;
    }));
  }
  std::int64_t& t = last_[worker];
  t = std::max(t, now_ms);
}

std::vector<std::pair<std::string, std::int64_t>> WorkersSeen::list(std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  std::erase_if(last_, [&](const auto& w) { return now_ms - w.second > forget_after_ms; });
  std::vector<std::pair<std::string, std::int64_t>> out(last_.begin(), last_.end());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace compaction::server
