// The 3D constitutive update (plasticity_3d.hpp) against closed-form answers and an independent
// oracle: uniaxial strain and uniaxial stress paths through yield, the elastic state left alone,
// the return landing on the yield surface with the volume kept, isotropy under rotations, and
// an oracle that forms the Hencky strain and the plastic correction as matrices (log and exp
// through their own decompositions) instead of in principal space. Each runs on return_map_3d
// (the power series, handing back what they do not hold) and on return_map_3d_principal (every
// state in principal space); the series alone are checked against the principal update and for
// where they hold.
#include "plasticity_3d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "splitmix64.hpp"

namespace compaction {
namespace {

constexpr double kE = 2.5e7, kNu = 0.3, kQy = 250.0;  // R = 1e-5, as the paper's example (a)

Material3D material(double q_y = kQy) {
  const double lambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  return {lambda, mu, q_y / (std::sqrt(6.0) * mu)};
}

double von_mises(const Mat3& t) {  // sqrt(3/2 s:s), s the 3D deviator
  const Mat3 s = t - t.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * s.cwiseProduct(s).sum());
}

// A uniformly random rotation (Shoemake's quaternion from three uniforms).
Mat3 random_rotation(SplitMix64& rng) {
  const double u1 = rng.uniform(), u2 = 2 * M_PI * rng.uniform(), u3 = 2 * M_PI * rng.uniform();
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                             std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
  return q.normalized().toRotationMatrix();
}

// A random elastic deformation gradient R1 diag(exp(e_i)) R2 with principal strains of size
// up to `amplitude` around a volumetric strain up to `volumetric`.
Mat3 random_fe(SplitMix64& rng, double amplitude, double volumetric) {
  const double v = volumetric * (2 * rng.uniform() - 1);
  Vec3 e;
  for (int i = 0; i < 3; ++i) e(i) = v / 3 + amplitude * (2 * rng.uniform() - 1);
  return random_rotation(rng) * e.array().exp().matrix().asDiagonal() * random_rotation(rng);
}

// The oracle: the Hencky strain as a matrix, the radial return on it, the correction exp(dev_new
// - dev) from a decomposition of its own.
struct Oracle {
  Mat3 fe, tau;
  double plastic;
};
Oracle oracle(const Mat3& fe, const Material3D& m) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(fe * fe.transpose());
  const Mat3 q = eig.eigenvectors();
  const Mat3 log_b = q * eig.eigenvalues().array().log().matrix().asDiagonal() * q.transpose();
  const Mat3 e = 0.5 * log_b;
  const Mat3 dev = e - e.trace() / 3 * Mat3::Identity();
  const double norm = dev.norm();
  const double scale = std::min(1.0, m.dev_yield / norm);
  const Mat3 dev_new = scale * dev;
  Oracle o;
  o.plastic = std::max(0.0, norm - m.dev_yield);
  // Fe <- exp(dev_new - dev) Fe, the exponential of a symmetric matrix through its eigenvectors
  Eigen::SelfAdjointEigenSolver<Mat3> cut(dev_new - dev);
  o.fe = cut.eigenvectors() * cut.eigenvalues().array().exp().matrix().asDiagonal() *
         cut.eigenvectors().transpose() * fe;
  o.tau = m.lambda * e.trace() * Mat3::Identity() + 2 * m.mu * (e.trace() / 3 * Mat3::Identity() + dev_new);
  return o;
}

// The update under test: return_map_3d or return_map_3d_principal.
using Update = double (*)(Mat3&, const Material3D&, Mat3&);
class Plasticity3dGtest : public ::testing::TestWithParam<Update> {
 protected:
  double update(Mat3& fe, const Material3D& m, Mat3& tau) const { return GetParam()(fe, m, tau); }
};

// Uniaxial strain F = diag(1, 1 - e, 1) in many increments, as the engine applies it. Closed
// form: e = diag(0, log J, 0), |dev(e)| = sqrt(2/3) |log J|, cut back to dev_yield; tau_i =
// (lambda + 2 mu / 3) log J + 2 mu dev_i; accumulated plastic strain sqrt(2/3) |log J| -
// dev_yield. Tolerance 1e-10 of |tau|: the update is exact, so only round-off over 1e5 steps
// remains.
TEST_P(Plasticity3dGtest, UniaxialStrainStressPathMatchesClosedFormThroughYield) {
  const Material3D m = material();
  Mat3 fe = Mat3::Identity(), tau;
  double plastic = 0.0;
  const int steps = 100000;
  const double e_max = 0.3;
  bool yielded = false;
  for (int n = 1; n <= steps; ++n) {
    const double e_old = e_max * (n - 1) / steps, e_new = e_max * n / steps;
    fe.row(1) *= (1 - e_new) / (1 - e_old);
    plastic += update(fe, m, tau);
    if (n % 997 != 0 && n != steps) continue;
    const double log_j = std::log(1 - e_new);
    const double norm = std::sqrt(2.0 / 3.0) * -log_j;
    yielded |= norm > m.dev_yield;
    const double s = std::min(1.0, m.dev_yield / norm);
    const Vec3 dev = s * log_j * Vec3(-1.0 / 3, 2.0 / 3, -1.0 / 3);
    const Vec3 expected = ((m.lambda + 2 * m.mu / 3) * log_j + 2 * m.mu * dev.array()).matrix();
    const double scale = expected.cwiseAbs().maxCoeff();
    ASSERT_LT((tau - Mat3(expected.asDiagonal())).cwiseAbs().maxCoeff(), 1e-10 * scale)
        << "e = " << e_new;
    ASSERT_NEAR(plastic, std::max(0.0, norm - m.dev_yield), 1e-10) << "e = " << e_new;
  }
  EXPECT_TRUE(yielded);
  EXPECT_NEAR(von_mises(tau), kQy, 1e-10 * kQy);  // on the yield surface, q = q_y exactly
}

// Uniaxial stress: the axial stretch imposed in increments, the lateral stretch (x = z) found
// each increment by secant iterations so that the lateral stress vanishes. Closed form
// (coaxial Hencky strains add): tau_yy = E eps until |tau_yy| = q_y, then -q_y (compression);
// accumulated plastic strain sqrt(3/2) (|eps| - q_y / E) (an isochoric axial cut (1, -1/2,
// -1/2) eps_p). R = 1e-3 here: stresses to 1e-10 q_y = 1e-13 E, far above the round-off of a
// stress computed from stretches near 1 (a stretch is resolved to 1.1e-16, which moves a stress
// by 2 (lambda + mu) 1.1e-16 ~ 5e-16 E); at R = 1e-5, 1e-10 q_y would be that round-off itself.
// The plastic strain, a sum of 1500 increments with ~1e-16 round-off each, to 1e-10 of its
// final value.
TEST_P(Plasticity3dGtest, UniaxialStressPathMatchesClosedFormThroughYield) {
  const double q_y = 1e-3 * kE;
  const Material3D m = material(q_y);
  const double yield_strain = q_y / kE;
  const int steps = 2000;
  const double eps_max = -4.0 * yield_strain;
  const double final_plastic = std::sqrt(1.5) * (-eps_max - yield_strain);
  Mat3 fe = Mat3::Identity(), tau;
  double plastic = 0.0;
  bool yielded = false;
  for (int n = 1; n <= steps; ++n) {
    const double d_eps = eps_max / steps;
    // Lateral stress of the trial update for a lateral log-stretch increment g.
    auto lateral = [&](double g, Mat3& f, Mat3& t) {
      f = Vec3(std::exp(g), std::exp(d_eps), std::exp(g)).asDiagonal() * fe;
      const double p = update(f, m, t);
      return std::pair{t(0, 0), p};
    };
    double g0 = -kNu * d_eps, g1 = 0.0;
    Mat3 f, t;
    double r0 = lateral(g0, f, t).first, r1 = lateral(g1, f, t).first;
    const double converged = 1e-11 * q_y;
    for (int it = 0; it < 50 && std::abs(r0) > converged && r0 != r1; ++it) {
      const double g2 = g0 - r0 * (g0 - g1) / (r0 - r1);
      g1 = g0, r1 = r0, g0 = g2;
      r0 = lateral(g0, f, t).first;
    }
    ASSERT_LE(std::abs(r0), converged) << "n = " << n;
    plastic += lateral(g0, fe, tau).second;
    const double eps = eps_max * n / steps;
    yielded |= -eps > yield_strain;
    ASSERT_NEAR(tau(1, 1), std::max(kE * eps, -q_y), 1e-10 * q_y) << "eps = " << eps;
    ASSERT_NEAR(tau(0, 0), 0.0, 1e-10 * q_y);
    ASSERT_NEAR(tau(2, 2), 0.0, 1e-10 * q_y);
    ASSERT_LT((tau - Mat3(tau.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 1e-10 * q_y);
    ASSERT_NEAR(plastic, std::sqrt(1.5) * std::max(0.0, -eps - yield_strain),
                1e-10 * final_plastic) << "eps = " << eps;
  }
  EXPECT_TRUE(yielded);
}

// Below yield the update changes nothing and returns 0 (bit for bit on Fe).
TEST_P(Plasticity3dGtest, ElasticStateIsLeftUnchanged) {
  const Material3D m = material(kQy * 1e6);  // yield far away: every state below is elastic
  SplitMix64 rng{3};
  for (int trial = 0; trial < 2000; ++trial) {
    const Mat3 fe0 = random_fe(rng, 0.05, 0.2);
    Mat3 fe = fe0, tau;
    EXPECT_EQ(update(fe, m, tau), 0.0);
    EXPECT_EQ(fe, fe0);
  }
}

// Past yield (up to 20 x the yield strain), the returned stress lies on the yield surface,
// q = q_y to 1e-10 relative, with the mean stress (3 lambda + 2 mu) / 3 log J kept.
TEST_P(Plasticity3dGtest, ReturnLandsOnYieldSurfaceAndKeepsVolume) {
  const Material3D m = material();
  SplitMix64 rng{5};
  int plastic_states = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Mat3 fe = random_fe(rng, 20 * kQy / kE, 0.1), tau;
    const double log_j = std::log(fe.determinant());
    const double plastic = update(fe, m, tau);
    EXPECT_NEAR(std::log(fe.determinant()), log_j, 1e-14);  // the cut is isochoric
    EXPECT_NEAR(tau.trace(), (3 * m.lambda + 2 * m.mu) * log_j, 1e-10 * std::abs(tau.trace()) + 1e-6);
    if (plastic > 0.0) {
      ++plastic_states;
      EXPECT_NEAR(von_mises(tau), kQy, 1e-10 * kQy);
    } else {
      EXPECT_LE(von_mises(tau), kQy * (1 + 1e-12));
    }
  }
  EXPECT_GT(plastic_states, 1500);  // the test exercises the return, not only elastic states
}

// Isotropy (frame indifference of the left stretch): Fe -> R Fe gives tau -> R tau R^T and
// Fe_out -> R Fe_out, elastic and plastic, from near-isotropic strains (1e-7, where the eigen
// vectors are ill-conditioned) to large ones (0.2). Tolerance: 1e-10 of |tau| and 1e-12 on Fe.
TEST_P(Plasticity3dGtest, RotatedInputGivesRotatedOutput) {
  SplitMix64 rng{9};
  for (double amplitude : {1e-7, 1e-5, 1e-3, 0.2}) {
    for (double q_y : {kQy, kQy * 1e4}) {
      const Material3D m = material(q_y);
      for (int trial = 0; trial < 500; ++trial) {
        const Mat3 fe0 = random_fe(rng, amplitude, 0.3), r = random_rotation(rng);
        Mat3 fe = fe0, tau, fe_r = r * fe0, tau_r;
        const double p = update(fe, m, tau), p_r = update(fe_r, m, tau_r);
        const double scale = tau.cwiseAbs().maxCoeff();
        EXPECT_LT((r * tau * r.transpose() - tau_r).cwiseAbs().maxCoeff(), 1e-10 * scale);
        EXPECT_LT((r * fe - fe_r).cwiseAbs().maxCoeff(), 1e-12);
        EXPECT_NEAR(p, p_r, 1e-12);
      }
    }
  }
}

// The principal-space update against the matrix form of the return (oracle above), over random
// states from near-isotropic to 20 x past yield.
// Tolerance 1e-10 of |tau| and 1e-12 on Fe and the plastic increment.
TEST_P(Plasticity3dGtest, MatchesMatrixFormOracle) {
  SplitMix64 rng{21};
  for (double amplitude : {1e-7, 1e-5, 2e-4, 0.1}) {
    const Material3D m = material();
    for (int trial = 0; trial < 1000; ++trial) {
      Mat3 fe = random_fe(rng, amplitude, 0.5), tau;
      const Oracle o = oracle(fe, m);
      const double p = update(fe, m, tau);
      const double scale = o.tau.cwiseAbs().maxCoeff();
      EXPECT_LT((tau - o.tau).cwiseAbs().maxCoeff(), 1e-10 * scale) << amplitude;
      EXPECT_LT((fe - o.fe).cwiseAbs().maxCoeff(), 1e-12) << amplitude;
      EXPECT_NEAR(p, o.plastic, 1e-12) << amplitude;
    }
  }
}

TEST_P(Plasticity3dGtest, InvertedOrNonFiniteStateIsReportedAsNan) {
  const Material3D m = material();
  Mat3 fe = Mat3::Identity(), tau;
  fe(1, 1) = -1.0;
  EXPECT_TRUE(std::isnan(update(fe, m, tau)));
  fe = Mat3::Identity();
  fe(0, 1) = std::nan("");
  EXPECT_TRUE(std::isnan(update(fe, m, tau)));
}

INSTANTIATE_TEST_SUITE_P(Updates, Plasticity3dGtest,
                         ::testing::Values(&return_map_3d, &return_map_3d_principal),
                         [](const auto& info) {
                           return std::string(info.index == 0 ? "Series" : "Principal");
                         });

// The power series against the principal update, where the series hold: random states from
// near-isotropic (1e-7) to strains of 0.05, elastic and past yield. Both are exact to round-off;
// the principal update resolves strains to a few ulp of |b| ~ 1 (2e-16 measured), so the
// tolerance is 1e-14 on the strain (tau / 2 mu), on Fe and on the plastic increment.
TEST(Plasticity3dSeriesGtest, AgreesWithPrincipalUpdate) {
  SplitMix64 rng{33};
  int series = 0, plastic_states = 0;
  for (double amplitude : {1e-7, 1e-5, 1e-3, 1e-2, 0.05}) {
    for (double q_y : {kQy, kQy * 1e3}) {
      const Material3D m = material(q_y);
      for (int trial = 0; trial < 1000; ++trial) {
        const Mat3 fe0 = random_fe(rng, amplitude, 0.1);
        Mat3 fe_s = fe0, tau_s, fe_p = fe0, tau_p;
        double p_s = 0.0;
        if (!return_map_3d_series(fe_s, m, tau_s, p_s)) continue;
        ++series, plastic_states += p_s > 0.0;
        const double p_p = return_map_3d_principal(fe_p, m, tau_p);
        EXPECT_LT((tau_s - tau_p).cwiseAbs().maxCoeff(), 1e-14 * 2 * m.mu) << amplitude;
        EXPECT_LT((fe_s - fe_p).cwiseAbs().maxCoeff(), 1e-14) << amplitude;
        EXPECT_NEAR(p_s, p_p, 1e-14) << amplitude;
      }
    }
  }
  EXPECT_GT(series, 8000);          // most states are in the series' range
  EXPECT_GT(plastic_states, 3000);  // and the plastic cut is exercised
}

// The series hold for the states a column meets: elastic principal strains up to 0.08 (a
// solid of q_y = 0.1 E yields at |dev(e)| = 0.106; stronger ones reach strains that the series
// leave to the principal update) and the plastic cut of one
// step, far below 2^-5. They hand back, with Fe and
// tau untouched, what they do not hold: a strain of 0.6 (|Z| > 1/4), a cut of 0.05 in one
// step, an inverted or non-finite state.
TEST(Plasticity3dSeriesGtest, HoldWhereTheColumnLivesAndHandBackTheRest) {
  const Material3D weak = material(), strong = material(0.1 * kE);
  SplitMix64 rng{35};
  for (int trial = 0; trial < 1000; ++trial) {
    Mat3 fe = random_fe(rng, 0.05, 0.1), tau;
    double plastic = -1.0;
    EXPECT_TRUE(return_map_3d_series(fe, strong, tau, plastic));
    EXPECT_EQ(plastic, 0.0);
    Mat3 f_step = Mat3::Identity();  // one step's cut past yield, as in the time step
    f_step(1, 1) = 1.0 - 2.0 * kQy / kE;
    EXPECT_TRUE(return_map_3d_series(f_step, weak, tau, plastic));
    EXPECT_GT(plastic, 0.0);
  }
  const Mat3 sentinel = Mat3::Constant(7.0);
  auto hands_back = [&](Mat3 fe, const Material3D& m) {
    const Mat3 fe0 = fe;
    Mat3 tau = sentinel;
    double plastic = -1.0;
    const bool held = return_map_3d_series(fe, m, tau, plastic);
    return !held && std::memcmp(fe.data(), fe0.data(), sizeof fe) == 0 && tau == sentinel &&
           plastic == -1.0;
  };
  Mat3 large = Mat3::Identity();  // a strain of 0.6: |Z| = tanh(0.6) = 0.54
  large(1, 1) = std::exp(-0.6);
  EXPECT_TRUE(hands_back(large, strong));
  Mat3 cut = Mat3::Identity();  // |dev(e)| = sqrt(2/3) 0.07 = 0.057 past a yield of 1e-5
  cut(1, 1) = std::exp(-0.07);
  EXPECT_TRUE(hands_back(cut, weak));
  Mat3 inverted = Mat3::Identity();
  inverted(1, 1) = -1.0;
  EXPECT_TRUE(hands_back(inverted, weak));
  Mat3 not_finite = Mat3::Identity();
  not_finite(0, 1) = std::nan("");
  EXPECT_TRUE(hands_back(not_finite, weak));
}

}  // namespace
}  // namespace compaction
