// Transfers: P2G conserves mass and momentum (stress forces sum to zero), APIC conserves the
// angular momentum of a spinning block and reproduces its affine velocity field exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "scene_builder.hpp"
#include "stages.hpp"
#include "threaded_grid.hpp"

namespace compaction {
namespace {

// A free block of particles in the middle of a full2d grid, far from plates and walls.
State spinning_block(double omega, double ux, double uy, Transfer transfer,
                     Gradient gradient = Gradient::mls) {
  SceneParams p;
  p.geometry = Geometry::full2d;
  p.n_cols = 4, p.n_rows = 4, p.cells_per_unit = 8, p.phi = 1.0, p.eps_end = 0.01;
  p.transfer = transfer;
  p.gradient = gradient;
  State s = build_scene(p);
  Particles& P = s.particles;
  const double L = p.unit_cell(), cx = 2 * L, cy = 2 * L;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < P.n; ++k) {
    if (std::abs(P.x[k] - cx) > 0.8 * L || std::abs(P.y[k] - cy) > 0.8 * L) continue;
    P.x[kept] = P.x[k] + 0.013 * L * std::sin(7.0 * k);  // irregular positions
    P.y[kept] = P.y[k] + 0.011 * L * std::cos(5.0 * k);
    ++kept;
  }
  P.n = kept;
  for (std::size_t k = 0; k < P.n; ++k) {
    P.vx[k] = ux - omega * (P.y[k] - cy);
    P.vy[k] = uy + omega * (P.x[k] - cx);
    P.C.set(k, {0, -omega, omega, 0});
    P.tau.set(k, {0, 0, 0});
  }
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
  return s;
}

struct Totals {
  double m = 0, px = 0, py = 0, L = 0;
};

Totals grid_totals(const State& s) {
  const Grid& g = s.grid;
  Totals t;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const Node& n = g.arrays.nodes[static_cast<std::size_t>(j) * g.nx + i];
      const double x = (i - g.gx) * g.dx, y = (j - g.gy) * g.dx;
      t.m += n.m, t.px += n.vx, t.py += n.vy;  // after P2G these are momenta
      t.L += x * n.vy - y * n.vx;
    }
  return t;
}

// Particle angular momentum including APIC's affine part: x_p x m v_p + m (B_p^T : eps),
// B = C D, D = dx^2/4 I (Jiang et al. 2015, Sec. 5.3).
Totals particle_totals(const State& s) {
  const Particles& P = s.particles;
  const double d = s.grid.dx * s.grid.dx / 4.0;
  Totals t;
  for (std::size_t k = 0; k < P.n; ++k) {
    t.m += P.mass, t.px += P.mass * P.vx[k], t.py += P.mass * P.vy[k];
    t.L += P.mass * (P.x[k] * P.vy[k] - P.y[k] * P.vx[k]) + P.mass * d * (P.C[k].yx - P.C[k].xy);
  }
  return t;
}

TEST(TransferGtest, ParticleToGridConservesMassMomentumAndAngularMomentum) {
  State s = spinning_block(3.0, 0.4, -0.25, Transfer::apic);
  ThreadPool pool(1);
  p2g(s, 0.0, pool);
  const Totals g = grid_totals(s), p = particle_totals(s);
  EXPECT_NEAR(g.m, p.m, 1e-13 * p.m);
  EXPECT_NEAR(g.px, p.px, 1e-12 * std::abs(p.px));
  EXPECT_NEAR(g.py, p.py, 1e-12 * std::abs(p.py));
  EXPECT_NEAR(g.L, p.L, 1e-12 * std::abs(p.L));
}

TEST(TransferGtest, StressForcesSumToZeroSoMomentumIsConserved) {
  for (Transfer tr : {Transfer::apic, Transfer::pic_flip})
  for (Gradient gr : {Gradient::mls, Gradient::bspline}) {
    State s = spinning_block(0.0, 0.3, 0.1, tr, gr);
    for (std::size_t k = 0; k < s.particles.n; ++k) {
      s.particles.tau.set(k, {1e4 * std::sin(k * 1.3), 2e3 * std::cos(k * 0.7), -5e3 + k});
    }
    ThreadPool pool(1);
    p2g(s, 1e-4, pool);  // stress impulse dt * f enters the momentum
    const Totals g = grid_totals(s), p = particle_totals(s);
    EXPECT_NEAR(g.px, p.px, 1e-10 * std::abs(p.px)) << to_string(tr) << to_string(gr);
    EXPECT_NEAR(g.py, p.py, 1e-10 * std::abs(p.py)) << to_string(tr) << to_string(gr);
  }
}

TEST(TransferGtest, ApicRoundTripReproducesRigidRotationAndKeepsAngularMomentum) {
  const double omega = 3.0;
  State s = spinning_block(omega, 0.0, 0.0, Transfer::apic);
  const Totals before = particle_totals(s);
  const std::vector<double> vx0 = s.particles.vx, vy0 = s.particles.vy;
  ThreadPool pool(1);
  for (int round = 0; round < 3; ++round) {  // dt = 0: transfers only, no motion
    p2g(s, 0.0, pool);
    grid_update(s, pool);
    g2p(s, 0.0, pool);
  }
  const Particles& P = s.particles;
  for (std::size_t k = 0; k < P.n; ++k) {
    ASSERT_NEAR(P.vx[k], vx0[k], 1e-12);
    ASSERT_NEAR(P.vy[k], vy0[k], 1e-12);
    ASSERT_NEAR(P.C[k].xy, -omega, 1e-10);
    ASSERT_NEAR(P.C[k].yx, omega, 1e-10);
  }
  EXPECT_NEAR(particle_totals(s).L, before.L, 1e-12 * std::abs(before.L));
}

// Threads scatter their own rows into the grid and shared rows into scratch
// (engine/src/scatter_rows.hpp): 2 and 3 threads give the serial grid to round-off, with APIC
// and with PIC/FLIP's extra momenta.
TEST(TransferGtest, ThreadedParticleToGridEqualsSerialToRoundOff) {
  for (Transfer transfer : {Transfer::apic, Transfer::pic_flip}) {
    State a = spinning_block(2.0, 0.1, 0.2, transfer);
    ThreadPool one(1);
    p2g(a, 1e-4, one);
    for (int threads : {2, 3}) {
      State b = spinning_block(2.0, 0.1, 0.2, transfer);
      size_for_threads(b, threads);
      ThreadPool pool(threads);
      p2g(b, 1e-4, pool);
      expect_same_nodes(a, b);
    }
  }
}

// The rows are only an economy: with the particles in an order that spreads every thread's
// share over the whole block (no row is any thread's own), the sum is the same.
TEST(TransferGtest, ThreadedParticleToGridIsRightForAnyParticleOrder) {
  State a = spinning_block(2.0, 0.1, 0.2, Transfer::apic);
  State b = spinning_block(2.0, 0.1, 0.2, Transfer::apic);
  Particles& P = b.particles;
  for (std::size_t k = 0; k + 1 < P.n; k += 2) {  // interleave the two halves
    const std::size_t j = P.n - 1 - k;
    if (j <= k) break;
    std::swap(P.x[k + 1], P.x[j]), std::swap(P.y[k + 1], P.y[j]);
    std::swap(P.vx[k + 1], P.vx[j]), std::swap(P.vy[k + 1], P.vy[j]);
    const Mat2 c = P.C[k + 1];
    const Sym2 t = P.tau[k + 1];
    P.C.set(k + 1, P.C[j]), P.tau.set(k + 1, P.tau[j]);
    P.C.set(j, c), P.tau.set(j, t);
  }
  size_for_threads(b, 2);
  ThreadPool one(1), two(2);
  p2g(a, 1e-4, one);
  p2g(b, 1e-4, two);
  expect_same_nodes(a, b);
  const ScatterRows& rows = b.grid.scatter_rows;
  EXPECT_LT(rows.lo[1], rows.lo[0] + 3);  // both shares span the block
  EXPECT_GT(rows.hi[1], rows.hi[0] - 3);
}

}  // namespace
}  // namespace compaction
