// The compiled copies of the hot particle loops (P2G, G2P): one for the x86-64 baseline (SSE2),
// one for AVX2 and one for AVX-512 (eight doubles a vector), the widest that the processor has
// chosen at run time (simd_copy()), and the four variants of each (transfer scheme x gradient),
// chosen per scene.
//
// Same bits in every copy: each vector instruction rounds each operation exactly as the scalar
// SSE2 one does, GCC does not reassociate (no -ffast-math), and no copy fuses a * b + c: the
// AVX-512 copy has FMA instructions, and -ffp-contract=off (engine/CMakeLists.txt) keeps GCC
// from contracting, which it does by default in C++ even under -std=c++20. So a result does
// not depend on the processor a worker runs on (tests/engine/simd_copies_gtest.cpp).
// A build for a processor with AVX2 (-march, COMPACTION_ARCH) or one without GCC's target
// attribute has one copy.
//
// How a stage makes its copies: it writes its loop once, as a class template
//   template <bool kApic, bool kExact> struct Loop {
//     template <bool kAvx2> [[gnu::always_inline]] static R run(...);
//   };
// (kAvx2: the copy being compiled has AVX2's four-double vectors, as the AVX-512 copy does too)
// and calls run_loop<Loop>(transfer, gradient, args...), which picks the variant and the copy:
// the loop is inlined once into a plain function and once into each wide one.
#pragma once

#include <type_traits>

#include "compaction/params.hpp"
#include "compaction/simd_copy.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX2__)
#define COMPACTION_HAS_WIDE_COPIES 1
#define COMPACTION_AVX2 __attribute__((target("avx2")))
// 512-bit vectors where the loop allows (GCC's default tuning would keep 256 bits).
#define COMPACTION_AVX512 \
  __attribute__((target("avx2,avx512f,avx512vl,avx512dq,prefer-vector-width=512")))
#else
#define COMPACTION_HAS_WIDE_COPIES 0
#define COMPACTION_AVX2
#define COMPACTION_AVX512
#endif

namespace compaction {

// The translation unit itself is compiled for AVX2 (-march with AVX2, COMPACTION_ARCH).
#ifdef __AVX2__
inline constexpr bool kCompiledForAvx2 = true;
#else
inline constexpr bool kCompiledForAvx2 = false;
#endif

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

#if COMPACTION_HAS_WIDE_COPIES
template <class Loop, class... Args>
COMPACTION_AVX2 auto avx2(Args... args) {
  return Loop::template run<true>(args...);
}

template <class Loop, class... Args>
COMPACTION_AVX512 auto avx512(Args... args) {
  return Loop::template run<true>(args...);
}
#endif

template <class Loop, class... Args>
auto either(Args... args) {
#if COMPACTION_HAS_WIDE_COPIES
  switch (simd_copy()) {
    case SimdCopy::avx512: return avx512<Loop, Args...>(args...);
    case SimdCopy::avx2: return avx2<Loop, Args...>(args...);
    case SimdCopy::baseline: break;
  }
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
