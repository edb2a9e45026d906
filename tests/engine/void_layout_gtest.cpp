// The voids of a random structure: inside their cells with the thinnest strut kept, areas that
// add up to the regular structure's, drawn from the seed; and the scene built from them.
#include "void_layout.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_builder.hpp"

namespace compaction {
namespace {

SceneParams random_scene(Geometry g, std::uint64_t seed) {
  SceneParams p;
  p.geometry = g, p.structure = Structure::random, p.seed = seed, p.phi = 0.4;
  p.cells_per_unit = 20, p.n_cols = 17, p.n_rows = 34;
  return p;
}

constexpr int kPerUnit = 40;  // 20 cells per unit cell, 2 particles per cell

VoidLayout layout(const SceneParams& p) {
  return void_layout(p, kPerUnit);
}

// The lattice margin the layout keeps to each cell edge: round(0.5 x 0.5 x 0.2254 x 40) = 2
// particles, so two neighbouring voids leave at least 4 particles (2 grid cells) of strut.
constexpr int kMargin = 2;

TEST(VoidLayoutGtest, RandomVoidsStayInsideTheirCellsAndKeepTheThinnestStrut) {
  for (Geometry g : {Geometry::pseudo1d, Geometry::full2d}) {
    const VoidLayout v = layout(random_scene(g, 3));
    ASSERT_EQ(v.voids.size(), static_cast<std::size_t>(v.cols) * v.rows);
    for (const Void& h : v.voids) {
      ASSERT_FALSE(h.empty());
      EXPECT_EQ(h.x1 - h.x0, h.y1 - h.y0);  // square
      EXPECT_GE(h.x0, kMargin);
      EXPECT_GE(h.y0, kMargin);
      EXPECT_LE(h.x1, kPerUnit - kMargin);
      EXPECT_LE(h.y1, kPerUnit - kMargin);
    }
  }
}

// Antithetic pairs make the open area the regular one's up to the rounding of each side to the
// lattice: half a particle at most on a side of ~31, an area error of 2 x 31 x e with e uniform
// in +-0.5, standard deviation 18 particles per void. Over 578 voids of 960 particles the sum
// is checked to 0.5 % of the open area, 6 standard deviations of independent roundings.
TEST(VoidLayoutGtest, RandomVoidAreasAddUpToTheRegularStructures) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const VoidLayout v = layout(random_scene(Geometry::full2d, seed));
    double open = 0.0;
    int smallest = kPerUnit, largest = 0;
    for (const Void& h : v.voids) {
      open += double(h.x1 - h.x0) * (h.y1 - h.y0);
      smallest = std::min(smallest, h.x1 - h.x0), largest = std::max(largest, h.x1 - h.x0);
    }
    const double expected = v.voids.size() * 0.6 * kPerUnit * kPerUnit;
    EXPECT_NEAR(open / expected, 1.0, 5e-3) << "seed " << seed;
    // The sides lie within 40 sqrt(0.42) = 25.9 and 40 sqrt(0.78) = 35.3, rounded; 289 uniform
    // areas in [0.7, 1.3] x 0.6 come within 2 % of the range (one particle of side) of each
    // end with probability 1 - 0.98^289 > 0.997.
    EXPECT_GE(smallest, 26) << "seed " << seed;
    EXPECT_LE(smallest, 27) << "seed " << seed;
    EXPECT_LE(largest, 35) << "seed " << seed;
    EXPECT_GE(largest, 34) << "seed " << seed;
  }
}

// The centres move: over the cells both ends of the admissible range are reached and the mean
// offset is near zero (578 offsets uniform in at most +-4.5 particles: standard error 0.11;
// checked to 0.5).
TEST(VoidLayoutGtest, RandomVoidCentresAreSpreadOverTheirRoom) {
  const VoidLayout v = layout(random_scene(Geometry::full2d, 5));
  double mean_x = 0.0, mean_y = 0.0;
  int at_low = 0, at_high = 0;
  for (const Void& h : v.voids) {
    mean_x += 0.5 * (h.x0 + h.x1) - 0.5 * kPerUnit;
    mean_y += 0.5 * (h.y0 + h.y1) - 0.5 * kPerUnit;
    at_low += h.x0 == kMargin, at_high += h.x1 == kPerUnit - kMargin;
  }
  EXPECT_NEAR(mean_x / v.voids.size(), 0.0, 0.5);
  EXPECT_NEAR(mean_y / v.voids.size(), 0.0, 0.5);
  EXPECT_GT(at_low, 0);
  EXPECT_GT(at_high, 0);
}

TEST(VoidLayoutGtest, TheSeedDecidesTheRandomStructure) {
  const SceneParams p = random_scene(Geometry::pseudo1d, 9);
  const VoidLayout a = layout(p), b = layout(p);
  SceneParams q = p;
  q.seed = 10;
  const VoidLayout c = layout(q);
  int differ = 0;
  for (std::size_t k = 0; k < a.voids.size(); ++k) {
    EXPECT_EQ(a.voids[k].x0, b.voids[k].x0);
    EXPECT_EQ(a.voids[k].y1, b.voids[k].y1);
    differ += a.voids[k].x0 != c.voids[k].x0 || a.voids[k].x1 != c.voids[k].x1 ||
              a.voids[k].y0 != c.voids[k].y0;
  }
  EXPECT_GT(differ, 17);  // most of the 34 voids
}

TEST(VoidLayoutGtest, RegularVoidsAreCentredAndAlike) {
  SceneParams p = random_scene(Geometry::full2d, 1);
  p.structure = Structure::regular;
  const VoidLayout v = layout(p);
  for (const Void& h : v.voids) {
    EXPECT_EQ(h.x1 - h.x0, 31);  // 40 sqrt(0.6) = 30.98
    EXPECT_EQ(h.x0, 4);          // (40 - 31) / 2
    EXPECT_EQ(h.y0, 4);
  }
}

// The scene's particles are the solid of the layout: realised phi near phi (34 voids: the
// rounding's standard deviation is sqrt(34) x 18 particles, 0.32 % of the open area; checked to
// 1.5 %), no particle inside a void, the plates' first and last particle rows solid.
TEST(VoidLayoutGtest, RandomSceneHasTheLayoutsSolidAndSolidRowsOnThePlates) {
  const SceneParams p = random_scene(Geometry::pseudo1d, 4);
  const State s = build_scene(p);
  const double phi = s.particles.n * s.particles.vol0 / (p.width() * p.h0);
  EXPECT_NEAR(phi, 0.4, 0.015 * 0.6);
  const double spacing = s.grid.dx / p.particles_per_cell;
  int bottom = 0, top = 0;
  for (std::size_t k = 0; k < s.particles.n; ++k) {
    bottom += s.particles.y[k] < spacing;
    top += s.particles.y[k] > p.h0 - spacing;
  }
  EXPECT_EQ(bottom, kPerUnit);
  EXPECT_EQ(top, kPerUnit);
  const VoidLayout v = layout(p);
  for (std::size_t k = 0; k < s.particles.n; ++k) {
    const int i = static_cast<int>(s.particles.x[k] / spacing);
    const int j = static_cast<int>(s.particles.y[k] / spacing);
    const Void& h = v.at(i / kPerUnit, j / kPerUnit);
    const int lx = i % kPerUnit, ly = j % kPerUnit;
    ASSERT_FALSE(lx >= h.x0 && lx < h.x1 && ly >= h.y0 && ly < h.y1) << k;
  }
}

}  // namespace
}  // namespace compaction
