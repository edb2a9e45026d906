// The two compiled copies of the hot particle loops (P2G, G2P): one for the x86-64 baseline
// (SSE2) and one for AVX2, chosen at run time (run_avx2_copy()), and the four variants of each
// (transfer scheme x gradient), chosen per scene.
//
// AVX2 only, not FMA: the vector instructions round each operation exactly as the scalar SSE2
// ones do, and GCC neither reassociates (no -ffast-math) nor fuses a * b + c (strict
// -std=c++20 means -ffp-contract=off), so both copies give the same result bits and a result
// does not depend on the processor a worker runs on (tests/engine/simd_copies_gtest.cpp).
// A build for a processor with AVX2 (-march, COMPACTION_ARCH) or one without GCC's target
// attribute has one copy.
//
// How a stage makes its copies: it writes its loop once, as a class template
//   template <bool kApic, bool kExact> struct Loop {
//     template <bool kAvx2> [[gnu::always_inline]] static R run(...);
//   };
// (kAvx2: the copy being compiled targets AVX2) and calls run_loop<Loop>(transfer, gradient,
// args...), which picks the variant and the copy: the loop is inlined once into a plain
// function and once into a COMPACTION_AVX2 one.
#pragma once

#include <type_traits>

#include "compaction/params.hpp"

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

namespace simd_copies {

// The copies take scalars by value and everything else by reference, as the loops do, so that
// they compile as the loops would on their own.
template <class T>
using Pass = std::conditional_t<std::is_scalar_v<std::remove_cvref_t<T>>, std::remove_cvref_t<T>,
                                T&&>;

template <class Loop, class... Args>
auto baseline(Args... args) {
  return Loop::template run<kCompiledForAvx2>(args...);
}

#if COMPACTION_HAS_AVX2_COPY
template <class Loop, class... Args>
COMPACTION_AVX2 auto avx2(Args... args) {
  return Loop::template run<true>(args...);
}
#endif

template <class Loop, class... Args>
auto either(Args... args) {
#if COMPACTION_HAS_AVX2_COPY
  if (run_avx2_copy()) return avx2<Loop, Args...>(args...);
#endif
  return baseline<Loop, Args...>(args...);
}

}  // namespace simd_copies

// Runs Loop::run<kAvx2>(args...), one variant, in the copy that this processor runs.
template <class Loop, class... Args>
auto run_variant(Args&&... args) {
  return simd_copies::either<Loop, simd_copies::Pass<Args>...>(args...);
}

// Runs Loop<kApic, kExact>::run<kAvx2>(args...) for the scene's transfer scheme and gradient,
// in the copy that this processor runs.
template <template <bool, bool> class Loop, class... Args>
auto run_loop(Transfer transfer, Gradient gradient, Args&&... args) {
  using simd_copies::either, simd_copies::Pass;
  const bool apic = transfer == Transfer::apic, exact = gradient == Gradient::bspline;
  if (apic && !exact) return either<Loop<true, false>, Pass<Args>...>(args...);
  if (apic) return either<Loop<true, true>, Pass<Args>...>(args...);
  if (!exact) return either<Loop<false, false>, Pass<Args>...>(args...);
  return either<Loop<false, true>, Pass<Args>...>(args...);
}

}  // namespace compaction
