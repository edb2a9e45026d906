// The front tracker on synthetic space-time maps with analytic fronts.
// Tolerances: positions are quantised to rows of 1/340 h0 and fitted over >= 0.1 of strain, so
// a speed is exact to about 0.3 %; 2 % leaves room for the leading edge of a Gaussian band
// being cut by the plate zone at the ends of the fit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "compaction/classify.hpp"
#include "synthetic_map.hpp"

namespace compaction::classify {
namespace {

using test::bump;
using test::features_of;
using test::make_run;

std::vector<const Front*> propagating(const FrontTracks& t) {
  std::vector<const Front*> out;
  for (const auto& f : t.fronts) if (f.propagating) out.push_back(&f);
  return out;
}

FrontTracks track(const test::SyntheticRun& s) {
  return track_fronts(s.result.spacetime, map_axes(s.params, s.result));
}

TEST(FrontTracker, SingleStraightFrontFromTheTopHasItsSpeedAndNoReflection) {
  const double c = 2.0;  // c / V
  const auto run = make_run(0.4, [&](double eps, double y) { return bump(y, 0.985 - c * eps); });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 1u);
  EXPECT_EQ(fronts[0]->origin, Origin::top);
  EXPECT_NEAR(fronts[0]->speed, c, 0.02 * c);
  EXPECT_EQ(fronts[0]->n_reflections, 0);
  EXPECT_NEAR(fronts[0]->path.back().centroid, 0.985 - c * 0.4, 0.01);
}

// The two readings of the speed agree on a straight front, each within its stated uncertainty
// (and both within the 2 % of the fit above).
TEST(FrontTracker, AStraightFrontsFittedAndTransitSpeedsAgreeWithinTheirUncertainties) {
  const double c = 2.0;
  const auto run = make_run(0.4, [&](double eps, double y) { return bump(y, 0.985 - c * eps); });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 1u);
  const Front& f = *fronts[0];
  EXPECT_NEAR(f.transit_speed, c, 0.02 * c);
  EXPECT_GT(f.speed_error, 0.0);
  EXPECT_LT(f.speed_error, 0.01 * c);   // a straight edge scatters by its rows only
  EXPECT_GT(f.transit_error, 0.0);
  // a row, a unit cell's step (sd 1/34 h0 / sqrt(12)) and half a frame at each end of a travel
  // of about 0.8 h0 over 0.4 of strain: 1.7 %
  EXPECT_LT(f.transit_error, 0.02 * c);
  EXPECT_LE(std::abs(f.speed - c), 3 * f.speed_error + 0.005 * c);  // + the edge's quantisation
  EXPECT_LE(std::abs(f.transit_speed - c), 3 * f.transit_error);
  const Features F = features_of(run, track(run));
  EXPECT_DOUBLE_EQ(F.band_speed_transit, f.transit_speed);
  EXPECT_DOUBLE_EQ(F.band_speed_transit_error, f.transit_error);
  EXPECT_DOUBLE_EQ(F.band_speed_error, f.speed_error);
}

// A band that slows down half way: the transit speed is the leg's mean (travel / strain), the
// fit lies between the two speeds, and its standard error shows that the edge is not straight.
TEST(FrontTracker, ABandThatSlowsDownHasTheMeanSpeedOfItsLegAsTransitAndAWideFit) {
  const double fast = 3.0, slow = 1.8, switch_eps = 0.12;
  const auto pos = [&](double eps) {
    return eps < switch_eps ? 0.985 - fast * eps : 0.985 - fast * switch_eps - slow * (eps - switch_eps);
  };
  const auto run = make_run(0.4, [&](double eps, double y) { return bump(y, pos(eps)); });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 1u);
  const Front& f = *fronts[0];
  EXPECT_GT(f.speed, slow);
  EXPECT_LT(f.speed, fast);
  // The straight edge above scatters by 5e-4 about its line; this one by ten times more.
  EXPECT_GT(f.speed_error, 0.005);
  // The leg runs to the end of the run: its mean speed is the travel over the strain (2 %, as
  // the fit above, for the edge's plate margin at the start).
  const double mean = (pos(0.0) - pos(0.4)) / 0.4;
  EXPECT_NEAR(f.transit_speed, mean, 0.02 * mean);
}

TEST(FrontTracker, FrontFromTheBottomMovesUpWithPositiveSpeed) {
  const double c = 1.5;
  const auto run = make_run(0.3, [&](double eps, double y) { return bump(y, 0.015 + c * eps); });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 1u);
  EXPECT_EQ(fronts[0]->origin, Origin::bottom);
  EXPECT_NEAR(fronts[0]->speed, c, 0.02 * c);
}

// Position of a band bouncing between the plates at speed c (the top plate moves at V).
double bouncing(double eps, double c) {
  double y = 0.985, dir = -1.0, e = 0.0;
  const double de = 1e-5;
  for (; e < eps; e += de) {
    y += dir * c * de;
    if (y <= 0.015) { y = 0.015; dir = 1.0; }
    if (y >= 0.985 - e) { y = 0.985 - e; dir = -1.0; }
  }
  return y;
}

TEST(FrontTracker, ReflectingFrontCountsEachReflectionAtAPlate) {
  const double c = 6.0;
  // Down (eps 0-0.16), up to the top (meets it at ~0.30), down again to the bottom (~0.42),
  // then up: reflections at the bottom, the top, the bottom.
  const auto run = make_run(0.46, [&](double eps, double y) { return bump(y, bouncing(eps, c)); });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 1u);
  const Front& f = *fronts[0];
  EXPECT_EQ(f.origin, Origin::top);
  EXPECT_EQ(f.n_reflections, 3);
  ASSERT_EQ(f.turns.size(), 3u);
  EXPECT_EQ(f.turns[0].where, Origin::bottom);
  EXPECT_EQ(f.turns[1].where, Origin::top);
  EXPECT_EQ(f.turns[2].where, Origin::bottom);
  EXPECT_NEAR(f.turns[0].eps, 0.97 / c, 0.006);  // three frames
  EXPECT_NEAR(f.speed, c, 0.02 * c);  // before the first reflection
}

TEST(FrontTracker, TwoCrossingFrontsKeepTheirIdentityThroughTheCrossing) {
  const double c_top = 3.0, c_bottom = 2.0;
  const auto run = make_run(0.3, [&](double eps, double y) {
    return bump(y, 0.985 - c_top * eps) + bump(y, 0.015 + c_bottom * eps);
  });
  const FrontTracks t = track(run);
  const auto fronts = propagating(t);
  ASSERT_EQ(fronts.size(), 2u);
  const Front* top = fronts[0]->origin == Origin::top ? fronts[0] : fronts[1];
  const Front* bottom = fronts[0]->origin == Origin::top ? fronts[1] : fronts[0];
  ASSERT_EQ(top->origin, Origin::top);
  ASSERT_EQ(bottom->origin, Origin::bottom);
  EXPECT_NEAR(top->speed, c_top, 0.02 * c_top);
  EXPECT_NEAR(bottom->speed, c_bottom, 0.02 * c_bottom);
  EXPECT_EQ(top->n_reflections, 0);
  EXPECT_EQ(bottom->n_reflections, 0);
  // They cross at eps = 0.97 / 5 = 0.194; afterwards each goes on in its own direction.
  EXPECT_LT(top->path.back().centroid, 0.985 - c_top * 0.25 + 0.02);
  EXPECT_GT(bottom->path.back().centroid, 0.015 + c_bottom * 0.25 - 0.02);

  const Features F = features_of(run, t);
  EXPECT_TRUE(F.two_sided);
  EXPECT_EQ(F.n_fronts_onset, 2);
  EXPECT_EQ(decide(F).label, "c");
}

// Class (c)'s two bands emerge at the onset. Fronts that start from both plates only after the
// first band has crossed the column (near densification, as in a reflecting band at 30 cells per
// unit cell on the Fig. 3 line, R = 1.4e-4) do not make a reflecting band two-sided.
TEST(FrontTracker, LateFrontsFromBothPlatesDoNotMakeABandTwoSided) {
  const double c = 2.5, c_late = 3.0, late = 0.45;
  const auto run = make_run(0.55, [&](double eps, double y) {
    if (eps < 0.385) return bump(y, 0.985 - c * eps);
    if (eps < late) return 0.0;
    return bump(y, 1.0 - late - 0.015 - c_late * (eps - late)) +
           bump(y, 0.015 + c_late * (eps - late));
  });
  const FrontTracks t = track(run);
  int top = 0, bottom = 0;
  for (const Front* f : propagating(t)) {
    top += f->origin == Origin::top;
    bottom += f->origin == Origin::bottom;
  }
  ASSERT_EQ(top, 2);     // the band and the late one
  ASSERT_EQ(bottom, 1);  // the late one
  const Features F = features_of(run, t);
  EXPECT_FALSE(F.two_sided);
  EXPECT_NE(decide(F).label, "c");
}

// Class (c)'s bands cross inside the sample: a bottom front counts when it starts before the
// top band has passed the middle (h0 / 2, where the material below the band is at rest). The same
// non-reflecting top band (c_b / V = 1.7, at the middle at eps = 0.285) with a bottom front
// rising at 2 V from eps = 0.2 is (c); from eps = 0.4, as the lowest rows of the map's runs at
// S = 3.2e-2 to 5.6e-2, R = 1.8e-3 to 8.9e-3 yield when the band nears them, it is not, and the
// band stays (a).
TEST(FrontTracker, ABottomFrontCountsOnlyIfItStartsBeforeTheTopBandPassesTheMiddle) {
  auto features_with_bottom_front_from = [](double start) {
    const double c_top = 1.7, c_bottom = 2.0;
    const auto run = make_run(0.55, [&](double eps, double y) {
      const double top = 0.985 - c_top * eps;
      const double bottom = 0.015 + c_bottom * (eps - start);
      return bump(y, top) + (eps >= start && bottom < top ? bump(y, bottom) : 0.0);
    });
    return features_of(run, track(run));
  };
  const Features early = features_with_bottom_front_from(0.2);
  EXPECT_TRUE(early.bottom_front);
  EXPECT_TRUE(early.two_sided);
  EXPECT_EQ(decide(early).label, "c");

  const Features late = features_with_bottom_front_from(0.4);
  EXPECT_TRUE(late.bottom_front);  // the front is found; it starts too late to count
  EXPECT_FALSE(late.two_sided);
  EXPECT_EQ(decide(late).label, "a");
}

// Mass conservation bounds a band's speed from below: c_b / V >= 1 / (1 - phi) = 1.67 here.
// The same straight front from the top is a non-reflecting band (a) at that speed and is not a
// band at all at 1.0 (activity drifting down, as erratic runs can show): (d). Stresses equal.
TEST(FrontTracker, AFrontSlowerThanMassConservationAllowsIsNotABand) {
  auto label_at = [](double c) {
    const auto run = make_run(0.4, [&](double eps, double y) { return bump(y, 0.985 - c * eps); });
    const FrontTracks t = track(run);
    return decide(features_of(run, t)).label;
  };
  EXPECT_EQ(label_at(1.0 / 0.6), "a");
  EXPECT_EQ(label_at(1.0), "d");
}

TEST(FrontTracker, RandomBlobsAreNotFronts) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Each frame: three blobs at uniformly random heights, independent between frames.
  const int frames = 100;
  std::vector<std::array<double, 3>> where(frames);
  for (auto& w : where) for (auto& y : w) y = 0.02 + 0.76 * u(rng);
  const auto run = make_run(0.002 * frames, [&](double eps, double y) {
    const auto& w = where[std::min(frames - 1, static_cast<int>(std::lround(eps / 0.002)) - 1)];
    return bump(y, w[0]) + 0.8 * bump(y, w[1]) + 0.6 * bump(y, w[2]);
  });
  const FrontTracks t = track(run);
  const Features F = features_of(run, t);
  // The most active row jumps by a third of the specimen on average: far above 2 cells.
  EXPECT_GT(F.peak_jump, 2.0);
  EXPECT_EQ(decide(F).label, "d");
}

TEST(FrontTracker, EmptyMapHasNoFrontAndIsUnclassified) {
  const auto run = make_run(0.1, [](double, double) { return 0.0; });
  const FrontTracks t = track(run);
  EXPECT_TRUE(t.fronts.empty());
  const Classification c = classify(run.params, run.result);
  EXPECT_EQ(c.label, "unclassified");
}

TEST(FrontTracker, RejectsAxesThatDoNotMatchTheMap) {
  auto run = make_run(0.1, [](double, double) { return 0.0; });
  MapAxes a = map_axes(run.params, run.result);
  a.eps.pop_back();
  EXPECT_THROW(track_fronts(run.result.spacetime, a), std::invalid_argument);
}

}  // namespace
}  // namespace compaction::classify
