// Which copy of the hot loops runs (simd_dispatch.hpp).
#include "simd_dispatch.hpp"

#include <algorithm>
#include <atomic>

#include "compaction/simd_copy.hpp"

namespace compaction {

namespace {

#if COMPACTION_HAS_WIDE_COPIES
// The widest copy that this processor runs.
SimdCopy widest_copy() {
  static const SimdCopy widest = __builtin_cpu_supports("avx512f") &&
                                         __builtin_cpu_supports("avx512vl") &&
                                         __builtin_cpu_supports("avx512dq")
                                     ? SimdCopy::avx512
                                 : __builtin_cpu_supports("avx2") ? SimdCopy::avx2
                                                                  : SimdCopy::baseline;
  return widest;
}
#endif

std::atomic<SimdCopy> widest_allowed{SimdCopy::avx512};

}  // namespace

SimdCopy simd_copy() {
#if COMPACTION_HAS_WIDE_COPIES
  return std::min(widest_copy(), widest_allowed.load(std::memory_order_relaxed));
#elif defined(__AVX512F__)
  return SimdCopy::avx512;  // a build for one instruction set (-march) has one copy
#else
  return kCompiledForAvx2 ? SimdCopy::avx2 : SimdCopy::baseline;
#endif
}

void use_simd_copy(SimdCopy c) { widest_allowed.store(c, std::memory_order_relaxed); }

const char* simd_copy_name(SimdCopy c) {
  switch (c) {
    case SimdCopy::avx512: return "avx512";
    case SimdCopy::avx2: return "avx2";
    case SimdCopy::baseline: break;
  }
  return "baseline";
}

}  // namespace compaction
