// The lease rescuer: a thread that, every interval, returns the jobs whose lease deadline passed
// (the worker died or lost the network) to the queue via QueueStore::requeue_expired, and then
// calls `after_expiry` (a job out of attempts has failed for good, which an adaptive sweep
// plans on).
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

#include "store/queue_store.hpp"

namespace compaction::server {

class LeaseRescuer {
 public:
  LeaseRescuer(QueueStore& queue, std::chrono::milliseconds interval,
               std::function<void()> after_expiry = {});
  ~LeaseRescuer();  // stops and joins the thread
  LeaseRescuer(const LeaseRescuer&) = delete;
  LeaseRescuer& operator=(const LeaseRescuer&) = delete;

 private:
  void run();

  QueueStore& queue_;
  std::chrono::milliseconds interval_;
  std::function<void()> after_expiry_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace compaction::server
