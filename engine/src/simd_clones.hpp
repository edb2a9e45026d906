// COMPACTION_SIMD_CLONES: compile a hot loop twice, for the x86-64 baseline (SSE2) and for AVX2,
// and let the loader pick the AVX2 copy on processors that have it (GCC function multiversioning,
// resolved once per process through an ifunc).
//
// AVX2 only, not FMA: the vector instructions round each operation exactly as the scalar SSE2
// ones do, and GCC neither reassociates (no -ffast-math) nor fuses a * b + c (strict
// -std=c++20 means -ffp-contract=off), so both copies give the same result bits, and a result
// does not depend on the processor a worker runs on (tests/engine/simd_clones_test.sh).
// A build with -march set (COMPACTION_ARCH) or a compiler without the attribute gets one copy.
//
// Used on the two particle loops: G2P, whose transfer and return mapping vectorise across a
// block of particles (four per instruction with AVX2), and P2G, whose node update is one
// four-lane operation on {m, m vx, m vy, 0}. Reference scene, one core: 53 ns per
// particle-step before the blocks, 47 ns with the baseline copy, 34 ns with the AVX2 copy
// (bench/results/engine_bench.md).
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX2__) && \
    !defined(COMPACTION_NO_SIMD_CLONES)
#define COMPACTION_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
// Where the two copies need different code (P2G's node update): a function compiled for AVX2,
// called when cpu_has_avx2().
#define COMPACTION_HAS_AVX2_COPY 1
#define COMPACTION_AVX2 __attribute__((target("avx2")))
inline bool cpu_has_avx2() { return __builtin_cpu_supports("avx2"); }
#else
#define COMPACTION_SIMD_CLONES
#define COMPACTION_HAS_AVX2_COPY 0
#endif

// The translation unit itself is compiled for AVX2 (-march with AVX2, COMPACTION_ARCH).
#ifdef __AVX2__
inline constexpr bool kCompiledForAvx2 = true;
#else
inline constexpr bool kCompiledForAvx2 = false;
#endif
