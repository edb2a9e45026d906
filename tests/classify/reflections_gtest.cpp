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

// A run whose band is a ramp of the row speed: at rest ahead of it but for `ahead` (the elastic
// precursor's velocity, a share of V), rising linearly from its leading edge lead(eps) to the
// plate speed at its trailing edge trail(eps), above which the material moves with the plate.
test::SyntheticRun with_ramp(double eps_end, double ahead,
                             const std::function<double(double)>& lead,
                             const std::function<double(double)>& trail) {
  test::SyntheticRun s = test::make_run(eps_end, [](double, double) { return 0.0; });
  SpaceTimeMap& v = s.result.velocity;
  v = s.result.spacetime;
  for (int f = 0; f < v.n_frames; ++f) {
    const double eps = s.result.frames[f].eps, lo = lead(eps), hi = trail(eps);
    for (int r = 0; r < v.n_rows; ++r) {
      const double y = (r + 0.5) / v.n_rows;
      const double speed = y > 1.0 - eps ? 0.0
                           : y >= hi     ? 1.0
                           : y <= lo     ? ahead
                                         : ahead + (1.0 - ahead) * (y - lo) / (hi - lo);
      v.values[static_cast<std::size_t>(f) * v.n_rows + r] = static_cast<float>(-speed);
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

// The early stage's edge speeds. Heights are read to a row (1/340 h0) in frames 0.002 of strain
// apart, and the fit spans the upper half of the column, about 0.18 of strain at these speeds:
// a row's error at both ends moves the slope by 2 / 340 / 0.18 = 0.033, the tolerance below.
constexpr double kEdgeSpeedTol = 0.033;

TEST(Reflections, SharpBandHasOneSpeedAtItsMiddleAndLeadingEdge) {
  const BandPath p = follow(with_band(0.4, [](double eps) { return 1.0 - 2.0 * eps; }));
  EXPECT_NEAR(p.middle.speed, 2.0, kEdgeSpeedTol);
  EXPECT_NEAR(p.lead.speed, 2.0, kEdgeSpeedTol);
  EXPECT_LT(p.middle.error, 0.01);
}

TEST(Reflections, WideningBandsLeadingEdgeRunsAheadOfItsMiddleWhateverTheMaterialAhead) {
  // Leading edge at 2.8 V, trailing edge at 2.1 V. The step's 10 % point lies a tenth of the
  // way from the leading to the trailing edge: 0.9 * 2.8 + 0.1 * 2.1 = 2.73 V, whatever the
  // precursor's velocity ahead of the band. Half the plate speed lies (0.5 - ahead) / (1 - ahead)
  // of the way: 2.8 - 0.7 (0.5 - ahead) / (1 - ahead).
  for (const double ahead : {0.0, 0.05, 0.3}) {
    SCOPED_TRACE(ahead);
    const BandPath p = follow(with_ramp(0.4, ahead, [](double eps) { return 1.0 - 2.8 * eps; },
                                        [](double eps) { return 1.0 - 2.1 * eps; }));
    EXPECT_NEAR(p.lead.speed, 2.73, kEdgeSpeedTol);
    EXPECT_NEAR(p.middle.speed, 2.8 - 0.7 * (0.5 - ahead) / (1.0 - ahead), kEdgeSpeedTol);
  }
}

TEST(Reflections, EarlyStageEndsAtTheFirstTurn) {
  // Down at 3 V to 0.55 h0 and back up: only the way down is the early stage (a fit over the
  // way up too would read a far smaller slope).
  auto band = [](double eps) { return eps < 0.15 ? 1.0 - 3.0 * eps : 0.55 + 2.0 * (eps - 0.15); };
  const BandPath p = follow(with_band(0.3, band));
  EXPECT_NEAR(p.middle.speed, 3.0, kEdgeSpeedTol);
  EXPECT_NEAR(p.lead.speed, 3.0, kEdgeSpeedTol);
}

TEST(Reflections, NoEarlyStageWithoutABandInTheUpperHalf) {
  // A band that forms at the bottom plate and runs up never has its edge in the upper half
  // before it turns: no early-stage speed.
  const BandPath p = follow(with_band(0.3, [](double eps) { return std::min(0.3, eps); }));
  EXPECT_TRUE(std::isnan(p.middle.speed));
  EXPECT_TRUE(std::isnan(p.lead.speed));
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
