// Wall-clock "now" for the store's time parameters (milliseconds since the Unix epoch).
#pragma once

#include <chrono>
#include <cstdint>

namespace compaction::server {

inline std::int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace compaction::server
