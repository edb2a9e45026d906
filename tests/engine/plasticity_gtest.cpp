// The constitutive update against closed-form answers: uniaxial strain through yield (Hencky +
// J2, the paper's sqrt(3/2 s:s) convention with the 2D deviator), frame indifference.
#include "plasticity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace compaction {
namespace {

constexpr double kE = 2.5e7, kNu = 0.3, kQy = 250.0;  // R = 1e-5, as the paper's example (a)

Material material() {
  const double lambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  return {lambda, mu, kQy / (std::sqrt(3.0) * mu)};
}

double von_mises(const Sym2& t) {  // sqrt(3/2 s:s), s the 2D deviator
  const double mean = 0.5 * (t.xx + t.yy);
  const double sxx = t.xx - mean, syy = t.yy - mean;
  return std::sqrt(1.5 * (sxx * sxx + syy * syy + 2 * t.xy * t.xy));
}

Mat2 mul(const Mat2& a, const Mat2& b) {
  return {a.xx * b.xx + a.xy * b.yx, a.xx * b.xy + a.xy * b.yy, a.yx * b.xx + a.yy * b.yx,
          a.yx * b.xy + a.yy * b.yy};
}

// Uniaxial strain F = diag(1, 1 - e), applied in many increments as the engine does. Closed form:
// log J = log(1 - e), d = e1 - e2 = min(-log J, d_y), tau_xx = (lambda + mu) log J + mu d,
// tau_yy = (lambda + mu) log J - mu d, accumulated plastic strain (-log J - d_y) / sqrt(2).
// Tolerance 1e-10 of |tau|: the update is exact, so only round-off over 1e5 steps remains.
TEST(PlasticityGtest, UniaxialStrainStressPathMatchesClosedFormThroughYield) {
  const Material m = material();
  Mat2 fe{1, 0, 0, 1};
  Sym2 tau{};
  double plastic = 0.0;
  const int steps = 100000;
  const double e_max = 0.3;
  bool yielded = false;
  for (int n = 1; n <= steps; ++n) {
    const double e_old = e_max * (n - 1) / steps, e_new = e_max * n / steps;
    fe = mul(Mat2{1, 0, 0, (1 - e_new) / (1 - e_old)}, fe);
    plastic += return_map(fe, m, tau);
    if (n % 997 != 0 && n != steps) continue;
    const double log_j = std::log(1 - e_new);
    const double d = std::min(-log_j, m.d_yield);
    yielded |= -log_j > m.d_yield;
    const double xx = (m.lambda + m.mu) * log_j + m.mu * d;
    const double yy = (m.lambda + m.mu) * log_j - m.mu * d;
    const double scale = std::abs(yy);
    ASSERT_NEAR(tau.xx, xx, 1e-10 * scale) << "e = " << e_new;
    ASSERT_NEAR(tau.yy, yy, 1e-10 * scale) << "e = " << e_new;
    ASSERT_NEAR(tau.xy, 0.0, 1e-10 * scale);
    ASSERT_NEAR(plastic, std::max(0.0, -log_j - m.d_yield) / std::sqrt(2.0), 1e-10);
  }
  EXPECT_TRUE(yielded);
  EXPECT_NEAR(von_mises(tau), kQy, 1e-10 * kQy);  // on the yield surface, q = q_y exactly
}

// The paper's convention: yield when sqrt(3/2 s:s) reaches q_y, with s = tau - tr(tau)/2 I.
// Matter's default prefactor sqrt(1/2) would put the onset at a strain sqrt(3) larger.
TEST(PlasticityGtest, YieldStartsWhereThreeHalvesDeviatorNormReachesQy) {
  const Material m = material();
  // Pure shear in principal axes: e1 = -e2 = g/2, so d = g, q = sqrt(3) mu g.
  const double g_yield = kQy / (std::sqrt(3.0) * m.mu);
  for (double f : {0.999, 1.001}) {
    const double g = f * g_yield;
    Mat2 fe{std::exp(g / 2), 0, 0, std::exp(-g / 2)};
    Sym2 tau{};
    const double plastic = return_map(fe, m, tau);
    if (f < 1) {
      EXPECT_EQ(plastic, 0.0);
      EXPECT_NEAR(von_mises(tau), f * kQy, 1e-9 * kQy);
    } else {
      EXPECT_GT(plastic, 0.0);
      EXPECT_NEAR(von_mises(tau), kQy, 1e-9 * kQy);
    }
  }
}

// A rigid rotation of a stressed, yielding state rotates the stress and the corrected Fe and
// changes no invariant (trace, von Mises stress, J, plastic increment).
TEST(PlasticityGtest, RigidRotationChangesNoInvariant) {
  const Material m = material();
  const Mat2 f0{1.00002, 0.00003, -0.00001, 0.99990};  // beyond yield: d ~ 1e-4 > d_y ~ 1.8e-5
  for (double angle : {0.3, 1.2, 2.5, -0.7}) {
    const double c = std::cos(angle), s = std::sin(angle);
    const Mat2 rot{c, -s, s, c};
    Mat2 a = f0, b = mul(rot, f0);
    Sym2 ta{}, tb{};
    const double pa = return_map(a, m, ta), pb = return_map(b, m, tb);
    EXPECT_GT(pa, 0.0);
    EXPECT_NEAR(pa, pb, 1e-12);
    EXPECT_NEAR(ta.xx + ta.yy, tb.xx + tb.yy, 1e-9 * kQy);
    EXPECT_NEAR(von_mises(ta), von_mises(tb), 1e-9 * kQy);
    EXPECT_NEAR(a.xx * a.yy - a.xy * a.yx, b.xx * b.yy - b.xy * b.yx, 1e-14);
    const Mat2 ra = mul(rot, a);  // corrected Fe rotates with the frame
    EXPECT_NEAR(ra.xx, b.xx, 1e-13);
    EXPECT_NEAR(ra.xy, b.xy, 1e-13);
    EXPECT_NEAR(ra.yx, b.yx, 1e-13);
    EXPECT_NEAR(ra.yy, b.yy, 1e-13);
    // tau_b = R tau_a R^T
    const double rxx = c * c * ta.xx - 2 * c * s * ta.xy + s * s * ta.yy;
    const double rxy = c * s * (ta.xx - ta.yy) + (c * c - s * s) * ta.xy;
    EXPECT_NEAR(tb.xx, rxx, 1e-8 * kQy);
    EXPECT_NEAR(tb.xy, rxy, 1e-8 * kQy);
  }
}

TEST(PlasticityGtest, InvertedElementIsReportedAsNan) {
  Mat2 fe{1, 0, 0, -0.5};
  Sym2 tau{};
  EXPECT_TRUE(std::isnan(return_map(fe, material(), tau)));
}

TEST(PlasticityGtest, IsotropicStateHasNoDeviator) {
  const Material m = material();
  Mat2 fe{0.99, 0, 0, 0.99};
  Sym2 tau{};
  EXPECT_EQ(return_map(fe, m, tau), 0.0);
  EXPECT_DOUBLE_EQ(tau.xx, tau.yy);
  EXPECT_NEAR(tau.xx, (m.lambda + m.mu) * 2 * std::log(0.99), 1e-9 * std::abs(tau.xx));
  EXPECT_EQ(tau.xy, 0.0);
}

}  // namespace
}  // namespace compaction

namespace compaction {
namespace {

// The series equal the library's functions to two units in the last place (4.5e-16 relative)
// over the range they cover, and hand over to them beyond.
TEST(PlasticityGtest, SeriesLogarithmAndAtanhMatchTheLibrary) {
  for (double x = 0.8; x < 1.25; x += 1e-4) {
    EXPECT_NEAR(log_near_one(x), std::log(x), 4.5e-16 * std::max(1.0, std::abs(std::log(x))));
  }
  for (double x = 0.6; x < 1.6; x += 1e-3) {  // the long series, |z| up to 1/4
    EXPECT_NEAR(log_near_one(x), std::log(x), 4.5e-16 * std::max(1.0, std::abs(std::log(x))));
  }
  for (double z : {0.0, 1e-12, -3e-7, 1e-3, 0.03, -0.031, 0.04, -0.1, 0.2, 0.249, 0.25, 0.5}) {
    EXPECT_NEAR(atanh_small(z), std::atanh(z), 4.5e-16 * std::abs(std::atanh(z)) + 1e-300);
  }
}

// The blocked return mapping (vectorised across particles) against the scalar one, on states
// from isotropic to far past yield. Where the block says its series hold, the elastic part is
// the scalar arithmetic step for step: tau and the plastic increment equal to the bit, and Fe
// too when nothing yields. Yielding Fe differs only in how cosh and sinh are rounded (series
// against exp): 1e-15 of |Fe|, a few units in the last place. Everything else is left to the
// scalar function (redo): out of the series' range, J <= 0, not finite.
TEST(PlasticityGtest, BlockReturnMapEqualsScalarOrHandsTheParticleBack) {
  for (const double R : {1e-5, 1e-3, 1e-1}) {
    const double lambda = (kQy / R) * kNu / ((1 + kNu) * (1 - 2 * kNu));
    const double mu = (kQy / R) / (2 * (1 + kNu));
    const Material m{lambda, mu, kQy / (std::sqrt(3.0) * mu)};
    ReturnMapBlock blk;
    std::vector<Mat2> trial;
    std::vector<bool> in_range;  // what the series cover, from the construction
    // principal stretches exp(+-d/2) J^(1/2), rotated by theta before and psi after
    for (const double d : {0.0, 1e-9, 0.3 * m.d_yield, 0.999 * m.d_yield, 1.001 * m.d_yield,
                           1.5 * m.d_yield, 0.02, 0.07, 0.6}) {
      for (const double J : {1.0, 0.999, 1.02, 0.9, 0.5}) {
        const double th = 0.3 + 7 * d, ps = -1.1 + 3 * J;
        const double s1 = std::sqrt(J) * std::exp(d / 2), s2 = std::sqrt(J) * std::exp(-d / 2);
        const Mat2 rt{std::cos(th), -std::sin(th), std::sin(th), std::cos(th)};
        const Mat2 rp{std::cos(ps), -std::sin(ps), std::sin(ps), std::cos(ps)};
        trial.push_back(mul(mul(rt, Mat2{s1, 0, 0, s2}), rp));
        in_range.push_back(std::tanh(d) < 0.25 && std::abs((J - 1) / (J + 1)) < 0.25 &&
                           (d - m.d_yield) / 2 < 1.0 / 32);
      }
    }
    trial.push_back({1, 0, 0, -0.5});          // inverted
    trial.push_back({std::nan(""), 0, 0, 1});  // not finite
    in_range.push_back(false), in_range.push_back(false);
    ASSERT_LE(trial.size(), kBlock);
    for (std::size_t i = 0; i < trial.size(); ++i) {
      blk.fxx[i] = trial[i].xx, blk.fxy[i] = trial[i].xy;
      blk.fyx[i] = trial[i].yx, blk.fyy[i] = trial[i].yy;
    }
    return_map_block<false>(blk, trial.size(), m);
    int short_handed_back = 0;
    for (std::size_t i = 0; i < trial.size(); ++i) short_handed_back += blk.redo[i] != 0.0;
    EXPECT_TRUE(any_redo(blk, trial.size()));
    EXPECT_GT(short_handed_back, 2 + 13);  // the short pass hands back more than the long one
    return_map_block<true>(blk, trial.size(), m);
    int handed_back = 0, yielded = 0;
    for (std::size_t i = 0; i < trial.size(); ++i) {
      Mat2 fe = trial[i];
      Sym2 tau{};
      const double plastic = return_map(fe, m, tau);
      SCOPED_TRACE(testing::Message() << "R " << R << " state " << i);
      ASSERT_EQ(blk.redo[i] != 0.0, !in_range[i]);
      if (!in_range[i]) {
        ++handed_back;
        continue;
      }
      ASSERT_TRUE(std::isfinite(plastic));
      EXPECT_EQ(blk.txx[i], tau.xx);
      EXPECT_EQ(blk.txy[i], tau.xy);
      EXPECT_EQ(blk.tyy[i], tau.yy);
      EXPECT_EQ(blk.plastic[i], plastic);
      const double scale =
          std::max({std::abs(fe.xx), std::abs(fe.xy), std::abs(fe.yx), std::abs(fe.yy)});
      const double tol = plastic > 0.0 ? 1e-15 * scale : 0.0;
      yielded += plastic > 0.0;
      EXPECT_NEAR(blk.exx[i], fe.xx, tol);
      EXPECT_NEAR(blk.exy[i], fe.xy, tol);
      EXPECT_NEAR(blk.eyx[i], fe.yx, tol);
      EXPECT_NEAR(blk.eyy[i], fe.yy, tol);
    }
    // The inverted and the NaN state always go back, and so do d = 0.6 and J = 0.5 (outside
    // the long series), 9 + 5 - 1 states.
    EXPECT_GE(handed_back, 2 + 13);
    if (R < 1e-2) {
      EXPECT_GT(yielded, 0);  // the comparison covered the plastic branch
    }
  }
}

}  // namespace
}  // namespace compaction
