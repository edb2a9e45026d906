// Conservation of the 3D column's transfers and step (p2g_3d, grid_update_3d, g2p_3d): mass on
// the grid equals the particles' mass, and in a free periodic box (no plate reached) total
// momentum is kept through many steps with random velocities, affine fields and stresses; on
// one thread and on two (p2g_3d's scratch grids and shared layers), and two threads give one
// thread's grid to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include <cmath>

#include "scene_builder_3d.hpp"
#include "splitmix64.hpp"
#include "stages_3d.hpp"
#include "step_3d.hpp"

namespace compaction {
namespace {

// A porous column of three unit cells, kept only in the middle one: at least L - 1.5 dx from
// either plate, so no plate node is reached; with V = 0 the top plate stays at h0.
State3D free_box(int threads = 1) {
  SceneParams p;
  p.threads = threads;
  p.geometry = Geometry::pseudo1d_3d;
  p.phi = 0.5;
  p.n_rows = 3;
  p.cells_per_unit = 6;
  p.S = 1e-3;
  State3D s = build_scene_3d(p);
  s.setup.V = 0.0;
  Particles3D& P = s.particles;
  const double L = p.unit_cell();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < P.n; ++i) {
    if (P.y[i] < L || P.y[i] > 2 * L) continue;
    P.x[kept] = P.x[i], P.y[kept] = P.y[i], P.z[kept] = P.z[i];
    ++kept;
  }
  P.n = kept;
  for (auto* v : {&P.x, &P.y, &P.z, &P.vx, &P.vy, &P.vz, &P.dep}) v->resize(kept);
  P.C.resize(kept), P.Fe.resize(kept), P.tau.resize(kept);
  // Random velocities (1 % of c_P), affine fields and elastic strains of 1e-4 (ten times the
  // yield strain at R = 1e-5: the return mapping acts too).
  SplitMix64 rng{42};
  auto u = [&] { return 2.0 * rng.uniform() - 1.0; };
  const double v0 = 0.01 * s.setup.c_p, c0 = v0 / L;
  for (std::size_t i = 0; i < kept; ++i) {
    P.vx[i] = v0 * u(), P.vy[i] = v0 * u(), P.vz[i] = v0 * u();
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        P.C[i](a, b) = c0 * u();
        P.Fe[i](a, b) = (a == b ? 1.0 : 0.0) + 1e-4 * u();
      }
    }
    return_map_3d(P.Fe[i], s.setup.material, P.tau[i]);
  }
  s.measure.y_min = L, s.measure.y_max = 2 * L;
  return s;
}

Vec3 momentum(const Particles3D& P) {
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < P.n; ++i) sum += P.mass * Vec3(P.vx[i], P.vy[i], P.vz[i]);
  return sum;
}

// Grid mass: sum of the particles' masses times weights that sum to one (1e-12 relative: the
// round-off of summing ~1e5 terms).
class Transfer3dThreads : public ::testing::TestWithParam<int> {};

TEST_P(Transfer3dThreads, ParticleToGridKeepsMassAndMomentum) {
  State3D s = free_box(GetParam());
  ThreadPool pool(GetParam());
  const double dt = stable_dt_3d(s, 0.5);
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
  p2g_3d(s, dt, pool);
  double mass = 0.0;
  Vec3 grid_momentum = Vec3::Zero();
  for (const Node3D& n : s.grid.nodes) mass += n.m, grid_momentum += Vec3(n.vx, n.vy, n.vz);
  const Particles3D& P = s.particles;
  EXPECT_NEAR(mass, P.n * P.mass, 1e-12 * P.n * P.mass);
  // The affine and stress parts sum to zero over each stencil (sum w d = 0): the grid's
  // momentum is the particles' (1e-12 of the momentum scale n m |v|).
  const double scale = P.n * P.mass * 0.01 * s.setup.c_p;
  EXPECT_LT((grid_momentum - momentum(P)).cwiseAbs().maxCoeff(), 1e-12 * scale);
}

// 50 steps of the whole recipe: momentum kept to 1e-11 of n m |v| (round-off of 50 steps of
// 1e5-term sums), the plates never act (no impulse), and the particles stay inside the box.
TEST_P(Transfer3dThreads, StepsInAFreePeriodicBoxKeepMomentum) {
  State3D s = free_box(GetParam());
  ThreadPool pool(GetParam());
  const Vec3 p0 = momentum(s.particles);
  const double scale = s.particles.n * s.particles.mass * 0.01 * s.setup.c_p;
  StageTimes times;
  for (int n = 0; n < 50; ++n) {
    const StepOutcome step = advance_step_3d(s, std::numeric_limits<double>::infinity(), 0.5, pool, times);
    ASSERT_FALSE(s.measure.bad_jacobian);
    ASSERT_FALSE(step.closes_frame);
  }
  EXPECT_LT((momentum(s.particles) - p0).cwiseAbs().maxCoeff(), 1e-11 * scale);
  EXPECT_EQ(s.clock.top_impulse, 0.0);
  EXPECT_EQ(s.clock.bottom_impulse, 0.0);
  EXPECT_GT(p0.cwiseAbs().maxCoeff(), 1e-3 * scale);  // a momentum to keep, not zero
}

INSTANTIATE_TEST_SUITE_P(Threads, Transfer3dThreads, ::testing::Values(1, 2));

// Two threads scatter the particles of the shared layers into a scratch grid and add it after:
// each node gets the same terms in another order, so the grids agree to round-off (1e-13 of a
// node's scale) and the particles after 20 steps to 1e-12 of the cell.
TEST(Transfer3dGtest, TwoThreadsGiveOneThreadsGridToRoundOff) {
  State3D one = free_box(1), two = free_box(2);
  ThreadPool pool1(1), pool2(2);
  const double dt = stable_dt_3d(one, 0.5);
  one.grid.row_lo = two.grid.row_lo = 0, one.grid.row_hi = two.grid.row_hi = one.grid.ny;
  p2g_3d(one, dt, pool1);
  p2g_3d(two, dt, pool2);
  const auto& near = two.grid.scatter_rows.near;
  ASSERT_TRUE(std::any_of(near.begin(), near.end(), [](std::uint8_t v) { return v != 0; }))
      << "the two shares meet in the middle: some layers are shared";
  const double m_scale = one.particles.mass, p_scale = one.particles.mass * 0.01 * one.setup.c_p;
  for (std::size_t k = 0; k < one.grid.nodes.size(); ++k) {
    const Node3D &a = one.grid.nodes[k], &b = two.grid.nodes[k];
    ASSERT_NEAR(a.m, b.m, 1e-13 * m_scale) << k;
    ASSERT_NEAR(a.vx, b.vx, 1e-13 * p_scale) << k;
    ASSERT_NEAR(a.vy, b.vy, 1e-13 * p_scale) << k;
    ASSERT_NEAR(a.vz, b.vz, 1e-13 * p_scale) << k;
  }
  StageTimes times;
  for (int n = 0; n < 20; ++n) {
    advance_step_3d(one, std::numeric_limits<double>::infinity(), 0.5, pool1, times);
    advance_step_3d(two, std::numeric_limits<double>::infinity(), 0.5, pool2, times);
  }
  for (std::size_t i = 0; i < one.particles.n; ++i) {
    ASSERT_NEAR(one.particles.y[i], two.particles.y[i], 1e-12 * one.grid.dx) << i;
  }
}

}  // namespace
}  // namespace compaction
