// Which compiled copy of the engine's hot loops runs. They are compiled three times, for the
// x86-64 baseline, for AVX2 and for AVX-512, with the same result bits; the widest copy that the
// processor runs is the default. use_simd_copy(c) makes the scenes started afterwards in this
// process run the widest copy no wider than c (tests, benchmarks); use_simd_copy(SimdCopy::avx512)
// returns to the default. A build for one instruction set (-march, COMPACTION_ARCH) has one copy,
// which use_simd_copy() does not change.
#pragma once

namespace compaction {

enum class SimdCopy { baseline, avx2, avx512 };  // ordered by width
SimdCopy simd_copy();  // the copy that a scene started now runs
void use_simd_copy(SimdCopy c);

// "baseline", "avx2" or "avx512"
const char* simd_copy_name(SimdCopy c);

}  // namespace compaction
