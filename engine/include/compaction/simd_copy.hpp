// Which compiled copy of the engine's hot loops runs. They are compiled twice, for the x86-64
// baseline and for AVX2, with the same result bits; the AVX2 copy runs where the processor has
// it. use_simd_copy(SimdCopy::baseline) makes the scenes started afterwards in this process run
// the baseline copy (tests, benchmarks); use_simd_copy(SimdCopy::avx2) returns to the default.
#pragma once

namespace compaction {

enum class SimdCopy { baseline, avx2 };
SimdCopy simd_copy();  // the copy that a scene started now runs
void use_simd_copy(SimdCopy c);

}  // namespace compaction
