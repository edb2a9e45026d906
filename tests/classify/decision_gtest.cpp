// The decision on given features (no run): the buckling rule's two conditions, and a run's
// stored features deciding as the computed ones did (features_from_json, the path by which a map
// is decided again without its bundles).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "compaction/classify.hpp"

namespace compaction::classify {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Features of a quasi-static run whose activity is erratic (class (d) unless its struts buckle):
// plate stresses equal, the most active row jumping by 4 cells, fronts carrying 20 %.
Features erratic_run() {
  Features F;
  F.primary_origin = "top";
  F.nonreflecting_speed = 1.0 / 0.6;
  F.band_speed_ratio = kNaN;
  F.speed_excess = kNaN;
  F.arrival_eps = kNaN;
  F.first_reflection_eps = kNaN;
  F.coherence = 0.2;
  F.peak_jump = 4.0;
  F.stress_ratio = 1.02;
  F.undulation_share = 0.1;
  F.eps_first_yield = 0.01;
  F.eps_reached = 0.6;
  return F;
}

TEST(Decision, StrutsThatDeflectFarBeforeTheyYieldAreF) {
  // The paper's example (f), S = 4e-3 and R = 1e-1 (R_crit = 0.07): the map's runs there deflect
  // 1.7 to 1.9 strut thicknesses, grown 4 decades.
  Features F = erratic_run();
  F.deflection_growth = 4.0;
  F.deflection_before_yield = 1.7;
  const Classification c = decide(F);
  EXPECT_EQ(c.label, "f");
  EXPECT_GT(c.confidence, 0.9);
}

TEST(Decision, GrowthFromRoundOffWithoutSizeIsNotBuckling) {
  // Below R_crit a strut yields before it can buckle: its deflection may grow 1-2 decades from
  // round-off, yet stays near 0.003 thicknesses, which adds 2 % of bending stress at yield.
  Features F = erratic_run();
  F.deflection_growth = 1.8;
  F.deflection_before_yield = 0.0034;
  const Classification c = decide(F);
  EXPECT_EQ(c.label, "d");
  EXPECT_LT(c.scores[5], 0.1);
}

TEST(Decision, SizeWithoutGrowthIsNotBuckling) {
  // A deflection that was already there at the first frame (no growth while elastic) is the
  // structure's shape, not an instability.
  Features F = erratic_run();
  F.deflection_growth = 0.1;
  F.deflection_before_yield = 0.5;
  EXPECT_EQ(decide(F).label, "d");
}

TEST(Decision, BucklingNeedsBothConditionsAtTheirThresholds) {
  // Each soft step is one half at its threshold (buckling_growth, buckling_size), and the
  // evidence is their product; 3 widths beyond both it is above 0.95^2.
  const DecisionSettings s;
  Features F = erratic_run();
  F.deflection_growth = s.buckling_growth;
  F.deflection_before_yield = s.buckling_size;
  EXPECT_NEAR(decide(F).scores[5], 0.25, 1e-12);
  F.deflection_growth = s.buckling_growth + 3 * s.buckling_width;
  F.deflection_before_yield = s.buckling_size * std::pow(10.0, 3 * s.buckling_size_width);
  EXPECT_GT(decide(F).scores[5], 0.95 * 0.95);
  // No deflection at all (a run that never yields stores 0) is no evidence.
  F.deflection_before_yield = 0.0;
  EXPECT_EQ(decide(F).scores[5], 0.0);
}

TEST(Decision, StoredFeaturesDecideAsComputedOnes) {
  Features F = erratic_run();
  F.deflection_growth = 1.3;
  F.deflection_before_yield = 0.012;
  F.onset_origins = {"top", "interior"};
  F.n_fronts = 3;
  F.band_turns = 2;
  F.band_speed_early = 2.14;
  F.band_speed_lead = 2.79;
  F.band_speed_lead_error = 0.01;
  const Classification direct = decide(F);
  // As summary.json stores it (NaN written as null), then read back.
  const nlohmann::json stored = nlohmann::json::parse(to_json(direct).dump());
  const Features back = features_from_json(stored["features"]);
  const Classification again = decide(back);
  EXPECT_EQ(again.label, direct.label);
  EXPECT_EQ(again.runner_up, direct.runner_up);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(again.scores[i], direct.scores[i]) << "class " << i;
  EXPECT_EQ(to_json(again).dump(), to_json(direct).dump());
  EXPECT_TRUE(std::isnan(back.band_speed_ratio));
  EXPECT_EQ(back.band_speed_lead, F.band_speed_lead);
  EXPECT_EQ(back.onset_origins, F.onset_origins);
}

TEST(Decision, StoredFeaturesOfTheWrongTypeAreRefusedByName) {
  nlohmann::json j = to_json(erratic_run());
  j["deflection_growth"] = "1.3";
  try {
    features_from_json(j);
    FAIL() << "a string accepted as deflection_growth";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("features.deflection_growth"), std::string::npos) << e.what();
  }
  EXPECT_THROW(features_from_json(nlohmann::json::array()), std::invalid_argument);
  nlohmann::json k = to_json(erratic_run());
  k["n_reflections"] = 1.5;
  EXPECT_THROW(features_from_json(k), std::invalid_argument);
  k["n_reflections"] = -1;
  EXPECT_THROW(features_from_json(k), std::invalid_argument);
  k["n_reflections"] = 1LL << 40;
  EXPECT_THROW(features_from_json(k), std::invalid_argument);
}

}  // namespace
}  // namespace compaction::classify
