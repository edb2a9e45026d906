// The struts' deflection at first yield (features.cpp, deflection_before_yield) on frames with
// the deflections and plastic fractions of real runs: an elastic instability that grows by
// decades per frame is carried on to where the plastic fraction crosses yield_fraction; a
// deflection that grows slowly, or not at all, is read as the last elastic frame has it.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "synthetic_map.hpp"

namespace compaction::classify::test {
namespace {

struct Sample {
  double plastic_fraction;
  double max_deflection;
};

// A run of frames every 0.002 of strain, without activity in its map, whose last frames carry
// `tail` (the frames before it: elastic, deflection at round-off).
Features features_with_tail(const std::vector<Sample>& tail) {
  SyntheticRun s = make_run(0.1, [](double, double) { return 0.0; });
  auto& fr = s.result.frames;
  for (auto& f : fr) {
    f.plastic_fraction = 0.0;
    f.max_deflection = 1e-15;
  }
  const std::size_t first = 20;  // eps = 0.042 onwards
  for (std::size_t i = 0; i < tail.size(); ++i) {
    fr[first + i].plastic_fraction = tail[i].plastic_fraction;
    fr[first + i].max_deflection = tail[i].max_deflection;
  }
  for (std::size_t i = first + tail.size(); i < fr.size(); ++i) fr[i] = fr[first + tail.size() - 1];
  return features_of(s, FrontTracks{});
}

TEST(StrutFeatures, ExplosiveBucklingIsCarriedToTheYieldCrossing) {
  // Example (f) (S = 4e-3, R = 0.1) at 8 cells across a strut, unperturbed, eps 0.052-0.060:
  // the deflection grows 1.6 decades a frame while 0.03-0.04 % of the particles yield, then
  // 1.9 % yield in one frame. The last elastic frame reads 0.0067 thickness, below the buckling
  // size of 0.01 (DecisionSettings), though the struts yield buckled.
  const Features F = features_with_tail(
      {{3e-4, 6.44e-6}, {3e-4, 1.67e-4}, {4e-4, 6.67e-3}, {1.91e-2, 3.87e-2}, {2.68e-2, 0.912}});
  const double rate = std::log10(6.67e-3 / 1.67e-4);           // decades per frame
  const double share = (0.01 - 4e-4) / (1.91e-2 - 4e-4);        // of the frame before yield
  const double carried = 6.67e-3 * std::pow(10.0, rate * share);  // 0.044
  EXPECT_NEAR(F.eps_first_yield, 0.048, 1e-12);
  // Capped at the yield frame's 0.0387: the deflection with which the struts yield.
  EXPECT_GT(carried, 3.87e-2);
  EXPECT_DOUBLE_EQ(F.deflection_before_yield, 3.87e-2);
  EXPECT_GT(F.deflection_before_yield, DecisionSettings{}.buckling_size);
  EXPECT_NEAR(F.deflection_growth, std::log10(6.67e-3 / 1e-9), 1e-9);
}

TEST(StrutFeatures, UncappedWhenTheYieldFrameDeflectsMore) {
  const Features F = features_with_tail({{0.0, 1e-4}, {0.0, 1e-3}, {0.02, 1.0}});
  // One decade a frame over half of the frame before yield: 1e-3 * 10^0.5.
  EXPECT_NEAR(F.deflection_before_yield, 1e-3 * std::sqrt(10.0), 1e-12);
}

TEST(StrutFeatures, SlowGrowthFromRoundOffStaysSmall) {
  // A deflection that grows a decade over ten frames from round-off and is large only once the
  // struts collapse plastically (the yield frame) is not carried to the collapse's size.
  std::vector<Sample> tail;
  for (int i = 0; i <= 10; ++i) tail.push_back({0.0, 1e-8 * std::pow(10.0, 0.1 * i)});
  tail.push_back({0.011, 0.5});
  const Features F = features_with_tail(tail);
  EXPECT_LT(F.deflection_before_yield, 1e-7 * std::pow(10.0, 0.1) * (1 + 1e-12));
  EXPECT_LT(F.deflection_before_yield, DecisionSettings{}.buckling_size);
}

TEST(StrutFeatures, ShrinkingDeflectionIsTheLastElasticFrames) {
  const Features F = features_with_tail({{0.0, 0.02}, {0.0, 0.01}, {0.05, 0.5}});
  EXPECT_DOUBLE_EQ(F.deflection_before_yield, 0.01);
}

}  // namespace
}  // namespace compaction::classify::test
