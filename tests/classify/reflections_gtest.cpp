// The band's path through the row velocity map and its reflections, on synthetic maps: above
// the band the material moves with the top plate (-1), below it is at rest (0).
// Positions are quantised to rows of 1/340 h0 and the path goes through a five-frame median, so
// a turn is found within a few frames (0.01 of strain) of where it happens.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "compaction/classify.hpp"
#include "synthetic_map.hpp"

namespace compaction::classify {
namespace {

// A run whose velocity map has the band at height band(eps) (in h0).
test::SyntheticRun with_band(double eps_end, const std::function<double(double)>& band) {
  test::SyntheticRun s = test::make_run(eps_end, [](double, double) { return 0.0; });
  SpaceTimeMap& v = s.result.velocity;
  v = s.result.spacetime;
  for (int f = 0; f < v.n_frames; ++f) {
    const double eps = s.result.frames[f].eps;
    for (int r = 0; r < v.n_rows; ++r) {
      const double y = (r + 0.5) / v.n_rows;
      v.values[static_cast<std::size_t>(f) * v.n_rows + r] =
          y > 1.0 - eps ? 0.0f : (y > band(eps) ? -1.0f : 0.0f);
    }
  }
  return s;
}

BandPath follow(const test::SyntheticRun& s) {
  return follow_band(s.result.velocity, map_axes(s.params, s.result), TrackerSettings{});
}

TEST(Reflections, NonReflectingBandCrossesOnceAndDoesNotTurn) {
  // c_b / V = 1 / (1 - phi): reaches the bottom as the sample becomes dense (eps = 0.6).
  const auto s = with_band(0.58, [](double eps) { return 1.0 - eps / 0.6; });
  const BandPath p = follow(s);
  EXPECT_EQ(p.n_reflections, 0);
  EXPECT_TRUE(std::isnan(p.first_reflection_eps));
  EXPECT_NEAR(p.height[100], 1.0 - 0.202 / 0.6, 0.01);
}

TEST(Reflections, ZigZagBandReflectsAtEachPlate) {
  // Down at 4 V to the bottom (eps 0.25), up at 3 V to the descending top plate
  // (1 - eps = 3 (eps - 0.25) at eps = 0.4375), down again.
  auto band = [](double eps) {
    if (eps < 0.25) return 1.0 - 4.0 * eps;
    if (eps < 0.4375) return 3.0 * (eps - 0.25);
    return (1.0 - 0.4375) - 4.0 * (eps - 0.4375);
  };
  const BandPath p = follow(with_band(0.55, band));
  EXPECT_EQ(p.n_reflections, 2);
  EXPECT_EQ(p.n_turns, 2);
  EXPECT_NEAR(p.first_reflection_eps, 0.25, 0.01);
}

TEST(Reflections, TurnAwayFromThePlatesIsNoReflection) {
  // Down to mid-height and back up: a turn in the interior.
  auto band = [](double eps) { return eps < 0.15 ? 1.0 - 3.0 * eps : 0.55 + 2.0 * (eps - 0.15); };
  const BandPath p = follow(with_band(0.3, band));
  EXPECT_EQ(p.n_reflections, 0);
  EXPECT_EQ(p.n_turns, 1);
}

TEST(Reflections, SeenReflectionMakesAReflectingBand) {
  // A band from the top at the non-reflecting speed that reflects early is (b), not (a): the
  // strain-rate map shows one front; the velocity map shows the reflection.
  auto s = with_band(0.4, [](double eps) { return eps < 0.3 ? 1.0 - eps / 0.3 : 3.0 * (eps - 0.3); });
  const double c = 1.0 / 0.6;
  for (int f = 0; f < s.result.spacetime.n_frames; ++f) {
    const double eps = s.result.frames[f].eps;
    for (int r = 0; r < s.result.spacetime.n_rows; ++r) {
      const double y = (r + 0.5) / s.result.spacetime.n_rows;
      if (y <= 1.0 - eps && eps < 0.3) {
        s.result.spacetime.values[static_cast<std::size_t>(f) * s.result.spacetime.n_rows + r] =
            static_cast<float>(test::bump(y, std::max(0.015, 0.985 - c * eps)));
      }
    }
  }
  const Features F =
      test::features_of(s, track_fronts(s.result.spacetime, map_axes(s.params, s.result)));
  EXPECT_EQ(F.n_reflections, 1);
  EXPECT_NEAR(F.first_reflection_eps, 0.3, 0.01);
  EXPECT_EQ(decide(F).label, "b");
}

}  // namespace
}  // namespace compaction::classify
