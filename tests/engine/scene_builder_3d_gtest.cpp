// The 3D column's initial state: the particle lattice with cubic holes, the grid and the
// constants of the scene.
#include "scene_builder_3d.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace compaction {
namespace {

SceneParams column(double phi, int cells) {
  SceneParams p;
  p.geometry = Geometry::pseudo1d_3d;
  p.phi = phi, p.n_rows = 3, p.cells_per_unit = cells, p.particles_per_cell = 2;
  p.movie_d_eps = 0.0, p.snapshot_eps = {};
  return p;
}

// phi = 0.5 at 10 cells: 20 particles per side, hole round(20 * 0.5^(1/3) = 15.87) = 16 of
// them, so 20^3 - 16^3 particles per unit cell, and the realised solid fraction 0.488.
TEST(SceneBuilder3dGtest, EachUnitCellHasACentredCubicHoleOfTheNearestParticleCount) {
  const SceneParams p = column(0.5, 10);
  ASSERT_TRUE(validate(p).empty());
  const State3D s = build_scene_3d(p);
  const Particles3D& P = s.particles;
  EXPECT_EQ(P.n, 3u * (20 * 20 * 20 - 16 * 16 * 16));
  const double L = p.unit_cell(), spacing = L / 20;
  EXPECT_NEAR(P.vol0, spacing * spacing * spacing, 1e-18);
  EXPECT_NEAR(P.mass, p.rho * P.vol0, 1e-15 * P.mass);
  // The hole spans particles [2, 18) of each cell in every direction: [0.1 L, 0.9 L).
  for (std::size_t i = 0; i < P.n; ++i) {
    ASSERT_GE(P.x[i], 0.0);
    ASSERT_LT(P.x[i], L);
    ASSERT_GE(P.z[i], 0.0);
    ASSERT_LT(P.z[i], L);
    const double yl = std::fmod(P.y[i], L);
    const bool inside = P.x[i] > 0.1 * L && P.x[i] < 0.9 * L && P.z[i] > 0.1 * L &&
                        P.z[i] < 0.9 * L && yl > 0.1 * L && yl < 0.9 * L;
    ASSERT_FALSE(inside) << i;
  }
  EXPECT_NEAR(P.n * P.vol0 / (L * L * p.h0), 1.0 - std::pow(16.0 / 20, 3), 1e-12);
}

TEST(SceneBuilder3dGtest, GridWrapsAcrossAndHasGhostLayersAlong) {
  const SceneParams p = column(0.4, 8);
  const State3D s = build_scene_3d(p);
  const Grid3D& g = s.grid;
  EXPECT_EQ(g.nx, 8);
  EXPECT_EQ(g.nz, 8);
  EXPECT_EQ(g.cells_y, 24);
  EXPECT_EQ(g.ny, 24 + 2 + 4);
  EXPECT_EQ(g.nodes.size(), g.layer() * g.ny);
  EXPECT_EQ(g.wrap.front(), 7);  // stencil column -1 is column 7
  EXPECT_EQ(g.wrap[1], 0);
  EXPECT_EQ(g.wrap.back(), 1);   // stencil column nx + 1 is column 1
  EXPECT_NEAR(s.setup.width, p.unit_cell(), 1e-15);
  // yield at |dev e| = q_y / (sqrt(6) mu): sqrt(3/2) |2 mu dev e| = q_y
  EXPECT_NEAR(std::sqrt(1.5) * 2 * s.setup.material.mu * s.setup.material.dev_yield, p.q_y,
              1e-12 * p.q_y);
}

}  // namespace
}  // namespace compaction
