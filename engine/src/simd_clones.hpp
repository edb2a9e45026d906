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
// Used where it pays: G2P, whose return mapping runs four particles per instruction with AVX2
// (53 -> 44 ns per particle-step on the reference scene). P2G's scatter gains nothing (its
// nine read-modify-writes per particle do not vectorise across particles).
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX2__) && \
    !defined(COMPACTION_NO_SIMD_CLONES)
#define COMPACTION_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define COMPACTION_SIMD_CLONES
#endif
