// The specimen as particles: solid fraction, holes, strut tags, periodic bounds, perturbation.
#include "scene_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace compaction {
namespace {

SceneParams scene(Geometry g, int cells, double phi) {
  SceneParams p;
  p.geometry = g, p.cells_per_unit = cells, p.phi = phi, p.n_cols = 3, p.n_rows = 4;
  return p;
}

double solid_fraction(const SceneParams& p, const State& s) {
  return s.particles.n * s.particles.vol0 / (p.width() * p.h0);
}

// The hole spans the whole number of particle columns nearest to L sqrt(1 - phi): the solid
// fraction is off by at most one particle column per hole side, 2 (1 - phi)^(1/2) / (2 cells)
// of the area to first order.
TEST(SceneBuilderGtest, SolidFractionIsPhiToOneParticleColumn) {
  for (double phi : {0.25, 0.4, 0.55, 0.75}) {
    for (int cells : {10, 20, 30}) {
      const SceneParams p = scene(Geometry::pseudo1d, cells, phi);
      const State s = build_scene(p);
      const double tolerance = 2.0 * std::sqrt(1.0 - phi) / (2.0 * cells);
      EXPECT_NEAR(solid_fraction(p, s), phi, tolerance) << "phi " << phi << " cells " << cells;
    }
  }
  const SceneParams p = scene(Geometry::pseudo1d, 20, 0.4);
  EXPECT_NEAR(solid_fraction(p, build_scene(p)), 0.39938, 1e-5);  // 31 of 40 columns open
}

TEST(SceneBuilderGtest, EveryCellHasItsHoleAndAllParticlesStayInTheSpecimen) {
  const SceneParams p = scene(Geometry::full2d, 10, 0.4);
  const State s = build_scene(p);
  const double L = p.unit_cell(), spacing = s.grid.dx / p.particles_per_cell;
  for (int cy = 0; cy < p.n_rows; ++cy)
    for (int cx = 0; cx < p.n_cols; ++cx) {
      bool occupied = false;
      for (std::size_t k = 0; k < s.particles.n; ++k) {
        if (std::abs(s.particles.x[k] - (cx + 0.5) * L) < 0.3 * L &&
            std::abs(s.particles.y[k] - (cy + 0.5) * L) < 0.3 * L) {
          occupied = true;
        }
      }
      EXPECT_FALSE(occupied) << "cell " << cx << "," << cy;
    }
  for (std::size_t k = 0; k < s.particles.n; ++k) {
    ASSERT_GT(s.particles.x[k], 0.0);
    ASSERT_LT(s.particles.x[k], p.width());
    ASSERT_GT(s.particles.y[k], 0.0);
    ASSERT_LT(s.particles.y[k], p.h0);
  }
  EXPECT_NEAR(s.particles.vol0, spacing * spacing, 1e-18);
  EXPECT_NEAR(s.particles.mass, p.rho * spacing * spacing, 1e-15);
}

TEST(SceneBuilderGtest, StrutsAreTaggedWithMiddlesAndEnds) {
  const SceneParams p = scene(Geometry::full2d, 10, 0.4);
  const State s = build_scene(p);
  EXPECT_EQ(s.setup.n_struts, (p.n_cols + 1) * p.n_rows);
  std::vector<int> mid(s.setup.n_struts), end(s.setup.n_struts);
  for (std::size_t k = 0; k < s.particles.n; ++k) {
    const int id = s.particles.strut[k];
    if (id < 0) continue;
    ASSERT_LT(id, s.setup.n_struts);
    (s.particles.strut_mid[k] ? mid : end)[id]++;
  }
  for (int id = 0; id < s.setup.n_struts; ++id) {
    EXPECT_GT(mid[id], 0) << id;
    EXPECT_GT(end[id], 0) << id;
  }
}

TEST(SceneBuilderGtest, PerturbationIsSeededBoundedAndKeepsPeriodicParticlesInside) {
  SceneParams p = scene(Geometry::pseudo1d, 10, 0.4);
  const State base = build_scene(p);
  p.perturbation = 0.3;
  const State a = build_scene(p), b = build_scene(p);
  const double spacing = base.grid.dx / p.particles_per_cell;
  ASSERT_EQ(a.particles.n, base.particles.n);
  double largest = 0.0;
  for (std::size_t k = 0; k < a.particles.n; ++k) {
    EXPECT_EQ(a.particles.x[k], b.particles.x[k]);
    EXPECT_GE(a.particles.x[k], 0.0);
    EXPECT_LT(a.particles.x[k], p.width());
    largest = std::max(largest, std::abs(a.particles.y[k] - base.particles.y[k]));
  }
  EXPECT_LE(largest, 0.3 * spacing);
  EXPECT_GT(largest, 0.2 * spacing);
}

}  // namespace
}  // namespace compaction
