// The two compiled copies of the hot particle loops (P2G, G2P): one for the x86-64 baseline
// (SSE2) and one for AVX2, chosen at run time (run_avx2_copy()).
//
// AVX2 only, not FMA: the vector instructions round each operation exactly as the scalar SSE2
// ones do, and GCC neither reassociates (no -ffast-math) nor fuses a * b + c (strict
// -std=c++20 means -ffp-contract=off), so both copies give the same result bits and a result
// does not depend on the processor a worker runs on (tests/engine/simd_copies_gtest.cpp).
// A build for a processor with AVX2 (-march, COMPACTION_ARCH) or one without GCC's target
// attribute has one copy.
//
// How a stage makes its two copies: the loop is an always-inline template, instantiated once
// in a plain function and once in a COMPACTION_AVX2 one, and the stage calls one of them.
// Reference scene, one core (bench/results/engine_bench.md): 57 ns per particle-step with the
// scalar loops of engine 0.2.0; the blocked loops run at 45 ns as the baseline copy and 27 ns
// as the AVX2 copy.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX2__)
#define COMPACTION_HAS_AVX2_COPY 1
#define COMPACTION_AVX2 __attribute__((target("avx2")))
#else
#define COMPACTION_HAS_AVX2_COPY 0
#define COMPACTION_AVX2
#endif

namespace compaction {

// The translation unit itself is compiled for AVX2 (-march with AVX2, COMPACTION_ARCH).
#ifdef __AVX2__
inline constexpr bool kCompiledForAvx2 = true;
#else
inline constexpr bool kCompiledForAvx2 = false;
#endif

// True when the stages should run their AVX2 copy: the build has one, the processor has AVX2
// and use_simd_copy(SimdCopy::baseline) has not been called.
bool run_avx2_copy();

}  // namespace compaction
