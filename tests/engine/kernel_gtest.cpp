// Invariants of the quadratic B-spline kernel: partition of unity, gradients summing to zero,
// linear reproduction and the APIC inertia tensor D = dx^2/4 that the MLS force relies on.
#include "kernel.hpp"

#include <gtest/gtest.h>

namespace compaction {

TEST(KernelGtest, WeightsSumToOneAndGradientsToZeroAcrossACell) {
  for (double xg = 3.0; xg < 4.0; xg += 1.0 / 97) {
    const auto s = kernel::quadratic(xg);
    EXPECT_NEAR(s.w[0] + s.w[1] + s.w[2], 1.0, 1e-15) << xg;
    EXPECT_NEAR(s.dw[0] + s.dw[1] + s.dw[2], 0.0, 1e-15) << xg;
    EXPECT_GE(s.fx, 0.5);
    EXPECT_LT(s.fx, 1.5);
  }
}

TEST(KernelGtest, ReproducesLinearFieldsAndHasInertiaOneQuarter) {
  for (double xg = 7.0; xg < 8.0; xg += 1.0 / 61) {
    const auto s = kernel::quadratic(xg);
    double first = 0, second = 0, grad_of_x = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = k - s.fx;  // node offset from the particle, in cells
      first += s.w[k] * d;
      second += s.w[k] * d * d;
      grad_of_x += s.dw[k] * (s.base + k);  // sum_i x_i dN_i/dx = 1
    }
    EXPECT_NEAR(first, 0.0, 1e-14) << xg;
    EXPECT_NEAR(second, 1.0 / kernel::kInverseInertia, 1e-14) << xg;
    EXPECT_NEAR(grad_of_x, 1.0, 1e-12) << xg;
  }
}

TEST(KernelGtest, DerivativeMatchesFiniteDifferenceOfWeights) {
  const double h = 1e-6;
  for (double xg = 2.55; xg < 3.45; xg += 0.1) {
    const auto s = kernel::quadratic(xg), a = kernel::quadratic(xg + h),
               b = kernel::quadratic(xg - h);
    ASSERT_EQ(a.base, b.base);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.dw[k], (a.w[k] - b.w[k]) / (2 * h), 1e-8);
  }
}

}  // namespace compaction
