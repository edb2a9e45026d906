// The closed-form return mapping (engine/src/plasticity.hpp) against an independent oracle
// built with Eigen over random states: the general (non-symmetric) eigen-decomposition of
// b = Fe Fe^T gives the Hencky strain eps = 1/2 log b, the radial return scales its deviator
// back to the yield surface in strain space, tau = lambda tr(eps) I + 2 mu eps, and the new
// elastic gradient is Fe' = exp(eps') exp(-eps) Fe with Eigen's matrix exponential (Pade
// scaling and squaring). Nothing of it shares the closed form's algebra (no atanh of 2r/(a+e),
// no projector N, no cosh/sinh correction).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>
#include <random>
#include <string>

#include "plasticity.hpp"

namespace compaction {
namespace {

using M2 = Eigen::Matrix2d;

struct Oracle {
  M2 fe;          // elastic deformation gradient after the return
  M2 tau;         // Kirchhoff stress
  double plastic;  // |plastic Hencky strain increment| (Frobenius norm of the deviator cut)
};

// log of a symmetric positive definite matrix through the general eigen-decomposition
// b = V diag(l) V^-1 (EigenSolver: Hessenberg reduction and real Schur form, not the symmetric
// solver); the eigenvalues of b are real and positive, and the test checks that they came out so.
M2 log_spd(const M2& b) {
  Eigen::EigenSolver<M2> es(b);
  EXPECT_EQ(es.info(), Eigen::Success);
  const Eigen::Vector2cd l = es.eigenvalues();
  const Eigen::Matrix2cd V = es.eigenvectors();
  EXPECT_EQ(l.imag().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(l.real().minCoeff(), 0.0);
  const Eigen::Matrix2cd L = l.array().log().matrix().asDiagonal();
  const Eigen::Matrix2cd logb = V * L * V.inverse();
  return logb.real();
}

Oracle oracle(const M2& fe, const Material& m) {
  const M2 eps = 0.5 * log_spd(fe * fe.transpose());
  const double vol = eps.trace();
  M2 dev = eps - 0.5 * vol * M2::Identity();
  // von Mises on the Kirchhoff deviator s = 2 mu dev: sqrt(3/2 s:s) <= q_y, the radial return
  // scales dev onto the surface; q_y = sqrt(3) mu d_yield (plasticity.hpp's convention).
  const double q = std::sqrt(1.5 * (2 * m.mu * dev).squaredNorm());
  const double q_y = std::sqrt(3.0) * m.mu * m.d_yield;
  double plastic = 0.0;
  if (q > q_y) {
    const M2 cut = dev * (1.0 - q_y / q);
    plastic = cut.norm();
    dev -= cut;
  }
  const M2 eps_new = dev + 0.5 * vol * M2::Identity();
  const M2 tau = m.lambda * vol * M2::Identity() + 2 * m.mu * eps_new;
  const M2 fe_new = eps_new.exp() * (-eps).exp() * fe;
  return {fe_new, tau, plastic};
}

Material material(double R) {
  const double nu = 0.3, q_y = 250.0, E = q_y / R;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  return {lambda, mu, q_y / (std::sqrt(3.0) * mu)};
}

M2 rotation(double t) {
  M2 r;
  r << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  return r;
}

// A random elastic gradient Fe = R(t1) diag(s1, s2) R(t2): principal log-stretches around a
// volumetric strain, with a principal difference up to `spread` times the yield difference,
// and two rotations uniform on the circle.
M2 random_state(std::mt19937_64& rng, const Material& m, double vol_range, double spread) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double vol = vol_range * (2 * u(rng) - 1);
  const double diff = spread * m.d_yield * u(rng);
  M2 s = M2::Zero();
  s(0, 0) = std::exp(0.5 * vol + 0.5 * diff);
  s(1, 1) = std::exp(0.5 * vol - 0.5 * diff);
  return rotation(2 * M_PI * u(rng)) * s * rotation(2 * M_PI * u(rng));
}

Mat2 to_mat2(const M2& f) { return {f(0, 0), f(0, 1), f(1, 0), f(1, 1)}; }

// Tolerances, from the oracle's own error: Eigen's eigen-decomposition and exponential are
// backward stable, a few ulp of |b| ~ 1, so its Hencky strain carries an absolute error of about
// 1e-15; we allow 1e-12 in strain, i.e. 1e-12 (lambda + 2 mu) in stress and 1e-12 in Fe (whose
// entries are of order 1), and 1e-12 in the plastic increment. The closed form itself is
// accurate to a few ulp of its strains (SeriesLogarithmAndAtanhMatchTheLibrary).
constexpr double kStrainTol = 1e-12;

struct Case {
  double R;          // q_y / E: 1e-5 (example a), 4e-4 (b), 0.1 (f: strong, large elastic strains)
  double vol_range;  // |log J| up to this
  double spread;     // principal strain difference up to spread x d_yield (< 1: elastic only)
};

class PlasticityEigen : public ::testing::TestWithParam<Case> {};

TEST_P(PlasticityEigen, ClosedFormReturnMappingAgreesWithTheEigenOracle) {
  const Case c = GetParam();
  const Material m = material(c.R);
  std::mt19937_64 rng(20221228);  // fixed: the same states on every run
  int plastic_states = 0;
  for (int n = 0; n < 4000; ++n) {
    const M2 f = random_state(rng, m, c.vol_range, c.spread);
    const Oracle o = oracle(f, m);
    Mat2 fe = to_mat2(f);
    Sym2 tau{};
    const double plastic = return_map(fe, m, tau);
    const double stress_tol = kStrainTol * (m.lambda + 2 * m.mu);
    ASSERT_NEAR(tau.xx, o.tau(0, 0), stress_tol) << "state " << n;
    ASSERT_NEAR(tau.xy, o.tau(0, 1), stress_tol) << "state " << n;
    ASSERT_NEAR(tau.yy, o.tau(1, 1), stress_tol) << "state " << n;
    ASSERT_NEAR(plastic, o.plastic, kStrainTol) << "state " << n;
    ASSERT_NEAR(fe.xx, o.fe(0, 0), kStrainTol) << "state " << n;
    ASSERT_NEAR(fe.xy, o.fe(0, 1), kStrainTol) << "state " << n;
    ASSERT_NEAR(fe.yx, o.fe(1, 0), kStrainTol) << "state " << n;
    ASSERT_NEAR(fe.yy, o.fe(1, 1), kStrainTol) << "state " << n;
    plastic_states += o.plastic > 0.0;

    // The blocked copy the time step runs (the particles it hands back run return_map above).
    ReturnMapBlock b;
    b.fxx[0] = f(0, 0), b.fxy[0] = f(0, 1), b.fyx[0] = f(1, 0), b.fyy[0] = f(1, 1);
    return_map_block<true>(b, 1, m);
    if (b.redo[0] == 0.0) {
      ASSERT_NEAR(b.txx[0], o.tau(0, 0), stress_tol) << "block, state " << n;
      ASSERT_NEAR(b.txy[0], o.tau(0, 1), stress_tol) << "block, state " << n;
      ASSERT_NEAR(b.tyy[0], o.tau(1, 1), stress_tol) << "block, state " << n;
      ASSERT_NEAR(b.plastic[0], o.plastic, kStrainTol) << "block, state " << n;
      ASSERT_NEAR(b.exx[0], o.fe(0, 0), kStrainTol) << "block, state " << n;
      ASSERT_NEAR(b.eyy[0], o.fe(1, 1), kStrainTol) << "block, state " << n;
    }
  }
  // The cases are built to cover what they are named for.
  if (c.spread < 1.0) EXPECT_EQ(plastic_states, 0);
  else EXPECT_GT(plastic_states, 1000);
}

// Weak solids (R = 1e-5, 4e-4) at the strains of the runs: compactions to J = e^-1.2 (past full
// density at phi = 0.4), elastic states and plastic trial states up to 20 times past yield; a
// strong solid (R = 0.1, yield difference 0.15) with elastic strains where atanh leaves its
// series.
INSTANTIATE_TEST_SUITE_P(
    RandomStates, PlasticityEigen,
    ::testing::Values(Case{1e-5, 1.2, 0.99}, Case{1e-5, 1.2, 20.0}, Case{4e-4, 0.5, 0.99},
                      Case{4e-4, 0.5, 20.0}, Case{0.1, 0.5, 0.99}, Case{0.1, 0.5, 3.0}),
    [](const ::testing::TestParamInfo<Case>& i) {
      std::string name = "Case";  // appended piece by piece: g++ 12 warns (-Wrestrict) on a + b + c
      name += std::to_string(i.index);
      name += i.param.spread < 1.0 ? "Elastic" : "Plastic";
      return name;
    });

}  // namespace
}  // namespace compaction
