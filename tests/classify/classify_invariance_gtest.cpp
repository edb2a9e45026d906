// At fixed S and R the dimensionless problem is the same for any yield strength q_y and density
// rho (the paper's Eq. 3): E = q_y / R, V = S sqrt(E / rho) and the time scale change, and the
// discrete equations change with them by scale factors only. The examples (a) and (b) with
// q_y x 40 and rho x 0.1 must give the same label, N_r and band speed to round-off. Run at 8
// cells per unit cell (about 5 s each): the symmetry holds at every resolution; that the
// labels are right needs a finer grid (classify_band_a_gtest, studies/validation/results/invariance.md).
#include <gtest/gtest.h>

#include "compaction/classify.hpp"
#include "compaction/simulation.hpp"

namespace compaction::classify {
namespace {

Classification run_and_classify(double R, double q_y, double rho) {
  SceneParams p;
  p.S = 4e-3;
  p.R = R;
  p.phi = 0.4;
  p.q_y = q_y;
  p.rho = rho;
  p.cells_per_unit = 8;
  p.eps_end = 0.2;
  p.snapshot_eps.clear();
  const RunResult r = run_scene(p);
  EXPECT_EQ(r.status, RunStatus::ok) << r.reason;
  return classify(p, r);
}

// Round-off of about 1e5 time steps in double, relative: far below any physical difference.
constexpr double kRoundOff = 1e-9;

void expect_same_pattern(double R) {
  const Classification base = run_and_classify(R, 250.0, 1000.0);
  const Classification scaled = run_and_classify(R, 1e4, 100.0);
  EXPECT_EQ(scaled.label, base.label);
  EXPECT_EQ(scaled.features.n_reflections, base.features.n_reflections);
  ASSERT_GT(base.features.band_speed_ratio, 0.0);
  EXPECT_NEAR(scaled.features.band_speed_ratio, base.features.band_speed_ratio,
              kRoundOff * base.features.band_speed_ratio);
  EXPECT_NEAR(scaled.features.band_speed_transit, base.features.band_speed_transit,
              kRoundOff * base.features.band_speed_transit);
  for (const auto speed : {&Features::band_speed_early, &Features::band_speed_lead}) {
    ASSERT_GT(base.features.*speed, 0.0);
    EXPECT_NEAR(scaled.features.*speed, base.features.*speed, kRoundOff * base.features.*speed);
  }
  EXPECT_NEAR(scaled.features.stress_ratio, base.features.stress_ratio,
              kRoundOff * base.features.stress_ratio);
}

TEST(ClassifyInvariance, ExampleAIsTheSameForAnyYieldStrengthAndDensityAtFixedSAndR) {
  expect_same_pattern(1e-5);
}

TEST(ClassifyInvariance, ExampleBIsTheSameForAnyYieldStrengthAndDensityAtFixedSAndR) {
  expect_same_pattern(4e-4);
}

}  // namespace
}  // namespace compaction::classify
