// The cost model (server/plan/cost_model.hpp) against what runs measured: the particles and the time
// steps of example (a) at 20 cells per unit cell (studies/savings/README.md), the factors of the other
// numerics, and the cost's growth with resolution (cells^3) and with 1 / S.
#include "plan/cost_model.hpp"

#include <gtest/gtest.h>

using namespace compaction;
using namespace compaction::server;

namespace {

// Example (a) of the paper at the default preset's grid.
SceneParams example_a() {
  SceneParams p;
  p.S = 4e-3;
  p.R = 1e-5;
  p.phi = 0.4;
  p.cells_per_unit = 20;
  p.eps_end = 0.6;
  p.pore_contact = PoreContact::single_field;  // the measured run's: one velocity field
  return p;
}

TEST(CostModel, particles_and_steps_match_the_measured_run_of_example_a) {
  const SceneParams p = example_a();
  // Exact: the model counts the lattice less its holes as the scene builder places them (21 726
  // measured, studies/savings/README.md).
  EXPECT_EQ(cost::particles(p), 21726);
  // The solid column (phi = 1) has no hole: 34 rows of 40 x 40.
  SceneParams solid = p;
  solid.phi = kSolidColumnPhi;
  EXPECT_EQ(cost::particles(solid), 34 * 40 * 40);
  // Tolerance 0.5 %: the model's fastest particle is the plate (V); the engine's step takes the
  // fastest particle each step (237 626 steps measured, studies/savings/README.md).
  EXPECT_NEAR(cost::steps(p), 237626, 0.005 * 237626);
  EXPECT_DOUBLE_EQ(cost::cpu_seconds(p),
                   cost::particles(p) * cost::steps(p) * cost::kNsPerParticleStep * 1e-9);
}

TEST(CostModel, cost_grows_as_cells_cubed_and_as_one_over_S) {
  SceneParams p = example_a();
  const double base = cost::cpu_seconds(p);
  p.cells_per_unit = 40;
  EXPECT_NEAR(cost::cpu_seconds(p) / base, 8.0, 1e-9);
  p = example_a();
  p.S = 2e-3;  // twice the steps, up to the +V in c_P + V
  EXPECT_NEAR(cost::cpu_seconds(p) / base, 2.0, 0.01);
  p = example_a();
  p.eps_end = 0.3;
  EXPECT_NEAR(cost::cpu_seconds(p) / base, 0.5, 1e-12);
}

TEST(CostModel, other_numerics_and_full_2d_cost_their_measured_factors) {
  const double base = cost::cpu_seconds(example_a());
  SceneParams p = example_a();
  p.transfer = Transfer::pic_flip;
  EXPECT_NEAR(cost::cpu_seconds(p) / base, cost::kPicFlipFactor, 1e-12);
  p = example_a();
  p.gradient = Gradient::bspline;
  EXPECT_NEAR(cost::cpu_seconds(p) / base, cost::kBsplineFactor, 1e-12);
  p = example_a();
  p.pore_contact = PoreContact::split_fields;
  EXPECT_NEAR(cost::cpu_seconds(p) / base, cost::kSplitFieldsFactor, 1e-12);
  p.pore_contact = PoreContact::automatic;  // costs what it resolves to
  EXPECT_NEAR(cost::cpu_seconds(p) / base, cost::kSplitFieldsFactor, 1e-12);
  p.cells_per_unit = 12;  // too coarse for two fields: one
  const double coarse = cost::cpu_seconds(p);
  p.pore_contact = PoreContact::single_field;
  EXPECT_EQ(cost::cpu_seconds(p), coarse);
  p = example_a();
  p.geometry = Geometry::full2d;  // 17 unit cells across
  EXPECT_NEAR(cost::particles(p) / cost::particles(example_a()), 17.0, 1e-12);
  EXPECT_NEAR(cost::cpu_seconds(p) / base, 17.0 * cost::kFull2dFactor, 1e-9);
}

TEST(CostModel, the_3d_column_counts_its_particles_in_three_dimensions_at_its_measured_factor) {
  // engine_bench's 3D column (bench/results/engine_bench.md): 8 cells per unit cell, 2 x 2 x 2
  // particles per cell, phi = 0.4, 64 566 particles built. Exact: the cubic hole is 13 of 16
  // particles across (16 cbrt(0.6) = 13.5 rounded), 34 rows of 16^3 - 13^3.
  SceneParams p = scene_defaults(Geometry::pseudo1d_3d);
  p.S = 4e-3;
  p.R = 1e-5;
  p.phi = 0.4;
  p.cells_per_unit = 8;
  p.particles_per_cell = 2;
  p.pore_contact = PoreContact::single_field;
  EXPECT_EQ(cost::particles(p), 64566);
  EXPECT_DOUBLE_EQ(cost::cpu_seconds(p), cost::particles(p) * cost::steps(p) *
                                             cost::kNsPerParticleStep * cost::k3dFactor * 1e-9);
  // The default preset resolves its pore contact to one field in 3D (no two-field 3D engine).
  p.pore_contact = PoreContact::automatic;
  EXPECT_DOUBLE_EQ(cost::cpu_seconds(p), cost::particles(p) * cost::steps(p) *
                                             cost::kNsPerParticleStep * cost::k3dFactor * 1e-9);
}

}  // namespace
