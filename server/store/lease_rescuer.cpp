#include "store/lease_rescuer.hpp"

#include <spdlog/spdlog.h>

#include "store/clock.hpp"

namespace compaction::server {

LeaseRescuer::LeaseRescuer(QueueStore& queue, std::chrono::milliseconds interval,
                           std::function<void()> after_expiry)
    : queue_(queue),
      interval_(interval),
      after_expiry_(std::move(after_expiry)),
      thread_([this] { run(); }) {}

LeaseRescuer::~LeaseRescuer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LeaseRescuer::run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, interval_, [this] { return stop_; })) {
    try {
      const int n = queue_.requeue_expired(now_ms());
      if (n > 0) {
        spdlog::warn("lease rescuer: {} expired lease(s) returned to the queue", n);
        if (after_expiry_) after_expiry_();
      }
    } catch (const std::exception& e) {
      spdlog::error("lease rescuer: {}", e.what());  // try again next interval
    }
  }
}

}  // namespace compaction::server
