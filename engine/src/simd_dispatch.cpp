// Which copy of the hot loops runs (simd_dispatch.hpp).
#include "simd_dispatch.hpp"

#include <atomic>

#include "compaction/simd_copy.hpp"

namespace compaction {

namespace {

bool cpu_has_avx2() {
#if COMPACTION_HAS_AVX2_COPY
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

std::atomic<bool> force_baseline{false};

}  // namespace

bool run_avx2_copy() {
  return COMPACTION_HAS_AVX2_COPY && cpu_has_avx2() &&
         !force_baseline.load(std::memory_order_relaxed);
}

SimdCopy simd_copy() {
  return kCompiledForAvx2 || run_avx2_copy() ? SimdCopy::avx2 : SimdCopy::baseline;
}

void use_simd_copy(SimdCopy c) { force_baseline.store(c == SimdCopy::baseline); }

}  // namespace compaction
