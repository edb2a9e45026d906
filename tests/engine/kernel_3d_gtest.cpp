// Invariants of the 3 x 3 x 3 quadratic B-spline stencil at random positions: partition of
// unity, zero first moment sum w (x_i - x_p) = 0 (linear reproduction, which APIC's angular
// momentum relies on), second moment D = dx^2 / 4 I (the MLS gradient's inertia), gradients
// summing to zero, and the gradient against a finite difference of the weights.
// Tolerance 1e-14: sums of 27 products of O(1) terms, a few ulp each.
#include "kernel_3d.hpp"

#include <gtest/gtest.h>

#include "splitmix64.hpp"

namespace compaction {
namespace {

// A random grid position, away from the ghost edge, and its stencil.
kernel::Stencil3D random_stencil(SplitMix64& rng, double& xg, double& yg, double& zg) {
  xg = 2.0 + 10.0 * rng.uniform();
  yg = 2.0 + 10.0 * rng.uniform();
  zg = 2.0 + 10.0 * rng.uniform();
  return kernel::quadratic_3d(xg, yg, zg);
}

// Offset of stencil node k from the particle, in cells, along axis d.
double offset(const kernel::Stencil3D& s, int k, int d, double xg, double yg, double zg) {
  const int a = k % 3, c = (k / 3) % 3, b = k / 9;
  if (d == 0) return s.x.base + a - xg;
  if (d == 1) return s.y.base + b - yg;
  return s.z.base + c - zg;
}

TEST(Kernel3dGtest, WeightsSumToOneAndFirstMomentAndGradientsToZeroAtRandomPositions) {
  SplitMix64 rng{7};
  for (int trial = 0; trial < 2000; ++trial) {
    double xg, yg, zg;
    const auto s = random_stencil(rng, xg, yg, zg);
    double sum = 0.0, moment[3] = {0, 0, 0}, grad[3] = {0, 0, 0};
    for (int k = 0; k < 27; ++k) {
      EXPECT_GE(s.w[k], 0.0);
      sum += s.w[k];
      for (int d = 0; d < 3; ++d) {
        moment[d] += s.w[k] * offset(s, k, d, xg, yg, zg);
        grad[d] += s.dw[k][d];
      }
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(moment[d], 0.0, 1e-14) << d;
      EXPECT_NEAR(grad[d], 0.0, 1e-14) << d;
    }
  }
}

TEST(Kernel3dGtest, SecondMomentIsOneQuarterTimesIdentity) {
  SplitMix64 rng{11};
  for (int trial = 0; trial < 500; ++trial) {
    double xg, yg, zg;
    const auto s = random_stencil(rng, xg, yg, zg);
    for (int d = 0; d < 3; ++d) {
      for (int e = 0; e < 3; ++e) {
        double m2 = 0.0;
        for (int k = 0; k < 27; ++k) {
          m2 += s.w[k] * offset(s, k, d, xg, yg, zg) * offset(s, k, e, xg, yg, zg);
        }
        EXPECT_NEAR(m2, d == e ? 1.0 / kernel::kInverseInertia : 0.0, 1e-14) << d << e;
      }
    }
  }
}

// sum_i x_i (x) grad w_i = I: the gradient reproduces linear fields exactly (1e-12: node
// coordinates up to 14 cells times gradients of O(1)).
TEST(Kernel3dGtest, GradientReproducesLinearFields) {
  SplitMix64 rng{13};
  for (int trial = 0; trial < 500; ++trial) {
    double xg, yg, zg;
    const auto s = random_stencil(rng, xg, yg, zg);
    for (int d = 0; d < 3; ++d) {
      for (int e = 0; e < 3; ++e) {
        double g = 0.0;
        for (int k = 0; k < 27; ++k) {
          g += (offset(s, k, d, xg, yg, zg) + (d == 0 ? xg : d == 1 ? yg : zg)) * s.dw[k][e];
        }
        EXPECT_NEAR(g, d == e ? 1.0 : 0.0, 1e-12) << d << e;
      }
    }
  }
}

// Central difference with h = 1e-6: truncation h^2 ~ 1e-12, rounding 1e-16 / h ~ 1e-10.
TEST(Kernel3dGtest, GradientMatchesFiniteDifferenceOfWeights) {
  SplitMix64 rng{17};
  const double h = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    double xg, yg, zg;
    const auto s = random_stencil(rng, xg, yg, zg);
    for (int d = 0; d < 3; ++d) {
      const double ex = d == 0 ? h : 0.0, ey = d == 1 ? h : 0.0, ez = d == 2 ? h : 0.0;
      const auto a = kernel::quadratic_3d(xg + ex, yg + ey, zg + ez);
      const auto b = kernel::quadratic_3d(xg - ex, yg - ey, zg - ez);
      if (a.x.base != b.x.base || a.y.base != b.y.base || a.z.base != b.z.base) continue;
      for (int k = 0; k < 27; ++k) EXPECT_NEAR(s.dw[k][d], (a.w[k] - b.w[k]) / (2 * h), 1e-8);
    }
  }
}

}  // namespace
}  // namespace compaction
