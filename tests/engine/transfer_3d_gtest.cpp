// Conservation of the 3D column's transfers and step (p2g_3d, grid_update_3d, g2p_3d): mass on
// the grid equals the particles' mass, and in a free periodic box (no plate reached) total
// momentum is kept through many steps with random velocities, affine fields and stresses.
#include <gtest/gtest.h>

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
State3D free_box() {
  SceneParams p;
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
TEST(Transfer3dGtest, ParticleToGridKeepsMassAndMomentum) {
  State3D s = free_box();
  const double dt = stable_dt_3d(s, 0.5);
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
  p2g_3d(s, dt);
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
TEST(Transfer3dGtest, StepsInAFreePeriodicBoxKeepMomentum) {
  State3D s = free_box();
  const Vec3 p0 = momentum(s.particles);
  const double scale = s.particles.n * s.particles.mass * 0.01 * s.setup.c_p;
  StageTimes times;
  for (int n = 0; n < 50; ++n) {
    const StepOutcome step = advance_step_3d(s, std::numeric_limits<double>::infinity(), 0.5, times);
    ASSERT_FALSE(s.measure.bad_jacobian);
    ASSERT_FALSE(step.closes_frame);
  }
  EXPECT_LT((momentum(s.particles) - p0).cwiseAbs().maxCoeff(), 1e-11 * scale);
  EXPECT_EQ(s.clock.top_impulse, 0.0);
  EXPECT_EQ(s.clock.bottom_impulse, 0.0);
  EXPECT_GT(p0.cwiseAbs().maxCoeff(), 1e-3 * scale);  // a momentum to keep, not zero
}

}  // namespace
}  // namespace compaction
