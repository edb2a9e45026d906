// Predicted regions (server/plan/phase_regions.hpp) on synthetic label fields: a known boundary is
// recovered to within the runs' spacing, uncertainty is high at the boundary, at low
// confidences and far from data and low inside a region, unlabelled runs do not vote, and the
// answer is the same bits for the same runs in any order.
#include "plan/phase_regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>

using namespace compaction::server;
using namespace compaction::server::regions;

namespace {

using Field = std::function<const char*(double x, double y)>;  // the label at (log S, log R)

// Runs on a lattice of `step` decades over [x0, x1] x [y0, y1], labelled by the field with
// confidence c and the other class of the field as runner-up.
std::vector<adaptive::Labelled> sample(const Field& f, double x0, double x1, double y0, double y1,
                                       double step, double c, const char* a, const char* b) {
  std::vector<adaptive::Labelled> out;
  const int nx = static_cast<int>(std::lround((x1 - x0) / step));
  const int ny = static_cast<int>(std::lround((y1 - y0) / step));
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const double x = x0 + i * step, y = y0 + j * step;
      const std::string l = f(x, y);
      out.push_back({{std::pow(10.0, x), std::pow(10.0, y)}, l, c, std::string(l == a ? b : a)});
    }
  }
  return out;
}

// The issue's box: S in [1e-3, 1e-1], R in [1e-5, 1e-1], sampled at 1/4 decade.
constexpr double kX0 = -3, kX1 = -1, kY0 = -5, kY1 = -1, kStep = 0.25;
const Box kIssueBox{kX0, kX1, kY0, kY1};

// A horizontal boundary at log10 R = -3.1 (between two rows of runs, at -3.25 and -3.0).
const Field kHorizontal = [](double, double y) { return y < -3.1 ? "a" : "b"; };
// A slanted one, log10 R = 2 log10 S + 1.9 (the slope of R/S^2 constant, Fig. 3's abscissa).
const Field kSlanted = [](double x, double y) { return y < 2 * x + 1.9 ? "e" : "b"; };

TEST(PhaseRegions, a_horizontal_boundary_is_recovered_to_half_the_runs_spacing) {
  const auto runs = sample(kHorizontal, kX0, kX1, kY0, kY1, kStep, 0.9, "a", "b");
  const Regions r = predict(runs, kIssueBox, 64);
  ASSERT_EQ(r.cells.size(), 64u * 64u);
  EXPECT_EQ(r.runs, runs.size());
  // Tolerance: the vote can only place the boundary between the two rows of runs that straddle
  // it (midway, by symmetry): within half the spacing, 0.125 decade, of the true one.
  int checked = 0;
  for (int i = 0; i < r.grid; ++i) {
    for (int j = 0; j < r.grid; ++j) {
      const double y = r.log_R(j);
      if (std::abs(y - (-3.1)) <= kStep / 2) continue;
      ASSERT_TRUE(r.at(i, j).cls);
      EXPECT_EQ(*r.at(i, j).cls, kHorizontal(r.log_S(i), y)) << "cell " << i << ", " << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 60 * 60);
}

TEST(PhaseRegions, a_slanted_boundary_is_recovered_to_half_the_runs_spacing) {
  const auto runs = sample(kSlanted, kX0, kX1, kY0, kY1, kStep, 0.9, "e", "b");
  const Regions r = predict(runs, kIssueBox, 80);
  int wrong = 0, checked = 0;
  for (int i = 0; i < r.grid; ++i) {
    for (int j = 0; j < r.grid; ++j) {
      const double x = r.log_S(i), y = r.log_R(j);
      // Distance to the line y = 2x + 1.9, against the runs' half spacing (as above) along the
      // diagonal of a lattice square, where straddling runs are farthest apart.
      const double d = std::abs(y - 2 * x - 1.9) / std::sqrt(5.0);
      if (d <= kStep * std::sqrt(2.0) / 2) continue;
      ++checked;
      if (!r.at(i, j).cls || *r.at(i, j).cls != kSlanted(x, y)) ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(checked, 80 * 80 / 2);
}

TEST(PhaseRegions, uncertainty_is_high_at_the_boundary_and_low_inside_a_region) {
  const auto runs = sample(kHorizontal, kX0, kX1, kY0, kY1, kStep, 0.9, "a", "b");
  // On the boundary, the rows on either side vote nearly alike: measured 0.93 at -3.1 with
  // confidence 0.9 (margin 0.07); more than half is what "uncertain" must mean on the map.
  for (double x : {-2.6, -2.0, -1.4}) {
    for (double y : {-3.2, -3.125, -3.05}) {
      EXPECT_GT(predict_at(runs, x, y).uncertainty, 0.5) << x << ", " << y;
    }
  }
  // Three quarters of a decade (3 h) from the boundary and inside the sampled area, the other
  // class weighs e^-4.5 of the near one: the uncertainty is the runs' own, 1 - c = 0.1, to 0.02.
  for (double x : {-2.6, -2.0, -1.4}) {
    for (double y : {-4.5, -4.0, -2.3, -1.6}) {
      const Cell c = predict_at(runs, x, y);
      EXPECT_NEAR(c.uncertainty, 0.1, 0.02) << x << ", " << y;
    }
  }
}

TEST(PhaseRegions, uncertainty_grows_far_from_data_and_there_is_no_class_past_the_cutoff) {
  // A 3 x 3 cluster of (a) at 1/4 decade around (-2, -3), all sure (confidence 1).
  const Field all_a = [](double, double) { return "a"; };
  const auto runs = sample(all_a, -2.25, -1.75, -3.25, -2.75, kStep, 1.0, "a", "b");
  EXPECT_LT(predict_at(runs, -2, -3).uncertainty, 0.01);
  // Rising with the distance from the cluster's edge (decades), then 1 without a class.
  double last = 0;
  for (double gap : {0.0, 0.25, 0.5, 0.75}) {
    const Cell c = predict_at(runs, -1.75 + gap, -3);
    ASSERT_TRUE(c.cls);
    EXPECT_EQ(*c.cls, "a");
    EXPECT_GT(c.uncertainty, last) << "gap " << gap;
    last = c.uncertainty;
  }
  // 3 h from the nearest runs: every vote is (a)'s (margin 1), so the uncertainty is
  // exp(-E / kEvidenceScale), E the kernel sum of the cluster's runs within the cutoff (0.025).
  double E = 0;
  for (const auto& r : runs) {
    const double dx = std::log10(r.point.S) - (-1.75 + 0.75), dy = std::log10(r.point.R) - (-3);
    const double d2 = dx * dx + dy * dy;
    if (d2 <= std::pow(kCutoffSigmas * kBandwidthDecades, 2)) {
      E += std::exp(-d2 / (2 * kBandwidthDecades * kBandwidthDecades));
    }
  }
  EXPECT_NEAR(E, 0.025, 0.001);
  EXPECT_NEAR(last, std::exp(-E / kEvidenceScale), 1e-12);
  EXPECT_GT(last, 0.85);
  const Cell far = predict_at(runs, -1.75 + 1.01, -3);
  EXPECT_FALSE(far.cls);
  EXPECT_EQ(far.uncertainty, 1.0);
  const Cell none = predict_at({}, -2, -3);
  EXPECT_FALSE(none.cls);
  EXPECT_EQ(none.uncertainty, 1.0);
}

TEST(PhaseRegions, a_label_of_low_confidence_is_uncertain_and_votes_for_its_runner_up) {
  const std::vector<adaptive::Labelled> sure{{{1e-2, 1e-3}, "b", 0.97, "c"}};
  const std::vector<adaptive::Labelled> doubtful{{{1e-2, 1e-3}, "b", 0.05, "c"}};
  // On the run: 1 - margin x reach with margin = c and reach = 1 - e^-5.
  const double reach = 1 - std::exp(-1 / kEvidenceScale);
  EXPECT_NEAR(predict_at(sure, -2, -3).uncertainty, 1 - 0.97 * reach, 1e-12);
  EXPECT_NEAR(predict_at(doubtful, -2, -3).uncertainty, 1 - 0.05 * reach, 1e-12);
  // A sure (d) next to a doubtful (b) whose runner-up is (d): (d) takes the midpoint.
  const std::vector<adaptive::Labelled> pair{{{1e-2, 1e-3}, "b", 0.05, "d"},
                                             {{1e-2, 1e-2}, "d", 0.9, "b"}};
  EXPECT_EQ(*predict_at(pair, -2, -2.5).cls, "d");
  // The same pair with equal confidences is a tie there: the first class in order, uncertain.
  const std::vector<adaptive::Labelled> tie{{{1e-2, 1e-3}, "b", 0.9, "d"},
                                            {{1e-2, 1e-2}, "d", 0.9, "b"}};
  const Cell t = predict_at(tie, -2, -2.5);
  EXPECT_EQ(*t.cls, "b");
  EXPECT_NEAR(t.uncertainty, 1.0, 1e-12);
}

TEST(PhaseRegions, runs_without_a_label_do_not_vote) {
  const auto runs = sample(kHorizontal, kX0, kX1, kY0, kY1, kStep, 0.9, "a", "b");
  auto with_failed = runs;
  for (double x : {-2.9, -2.1, -1.3}) {
    with_failed.push_back({{std::pow(10.0, x), 1e-3}, std::nullopt, 0.0, std::nullopt});
  }
  const Regions a = predict(runs, kIssueBox, 32), b = predict(with_failed, kIssueBox, 32);
  EXPECT_EQ(b.runs, runs.size());
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    EXPECT_EQ(a.cells[k].cls, b.cells[k].cls);
    EXPECT_EQ(a.cells[k].uncertainty, b.cells[k].uncertainty);
  }
}

TEST(PhaseRegions, the_same_runs_in_any_order_give_the_same_bits) {
  auto runs = sample(kSlanted, kX0, kX1, kY0, kY1, kStep, 0.6, "e", "b");
  const Regions first = predict(runs, kIssueBox, 48);
  std::mt19937 rng(7);
  for (int k = 0; k < 3; ++k) {
    std::shuffle(runs.begin(), runs.end(), rng);
    const Regions again = predict(runs, kIssueBox, 48);
    ASSERT_EQ(again.cells.size(), first.cells.size());
    for (std::size_t c = 0; c < first.cells.size(); ++c) {
      ASSERT_EQ(again.cells[c].cls, first.cells[c].cls);
      ASSERT_EQ(std::memcmp(&again.cells[c].uncertainty, &first.cells[c].uncertainty,
                            sizeof(double)),
                0);
    }
  }
}

TEST(PhaseRegions, a_cell_of_the_grid_is_the_rule_at_its_centre_to_the_bit) {
  const auto runs = sample(kSlanted, kX0, kX1, kY0, kY1, kStep, 0.6, "e", "b");
  const Regions r = predict(runs, kIssueBox, 24);
  for (int i = 0; i < r.grid; i += 5) {
    for (int j = 0; j < r.grid; j += 3) {
      const Cell c = predict_at(runs, r.log_S(i), r.log_R(j));
      EXPECT_EQ(c.cls, r.at(i, j).cls);
      EXPECT_EQ(std::memcmp(&c.uncertainty, &r.at(i, j).uncertainty, sizeof(double)), 0);
    }
  }
}

TEST(PhaseRegions, the_box_covers_the_points_padded_and_at_least_a_decade_wide) {
  EXPECT_FALSE(box_of({}));
  const auto b = box_of({{1e-3, 1e-5}, {1e-1, 1e-1}, {1e-2, 0.0}});  // R = 0 has no log: skipped
  ASSERT_TRUE(b);
  EXPECT_DOUBLE_EQ(b->log_S_min, -3 - kPadDecades);
  EXPECT_DOUBLE_EQ(b->log_S_max, -1 + kPadDecades);
  EXPECT_DOUBLE_EQ(b->log_R_min, -5 - kPadDecades);
  EXPECT_DOUBLE_EQ(b->log_R_max, -1 + kPadDecades);
  const auto one = box_of({{1e-2, 1e-3}});
  ASSERT_TRUE(one);
  EXPECT_DOUBLE_EQ(one->log_S_max - one->log_S_min, kMinSpanDecades + 2 * kPadDecades);
  EXPECT_DOUBLE_EQ((one->log_S_max + one->log_S_min) / 2, -2);
  // Cell centres divide the box evenly.
  Regions r;
  r.box = *b;
  r.grid = 4;
  EXPECT_DOUBLE_EQ(r.log_S(0), b->log_S_min + (b->log_S_max - b->log_S_min) / 8);
  EXPECT_DOUBLE_EQ(r.log_R(3), b->log_R_max - (b->log_R_max - b->log_R_min) / 8);
}

}  // namespace

// A point's replicates vote as one point (Labelled::share = 1 / its labelled runs): four
// replicates split 3:1 between (a) and (b) against one run (b) at the same distance on the
// other side give (b) the middle, 0.75 against 1.25 of a run's weight; counted as four runs
// they would give it to (a), 3 against 2.
TEST(PhaseRegions, a_points_replicates_vote_as_one_point_with_its_probabilities) {
  using compaction::server::adaptive::Labelled;
  std::vector<Labelled> runs;
  for (const char* label : {"a", "a", "a", "b"}) {
    Labelled l{{1e-2, std::pow(10.0, -2.5)}, std::string(label), 1.0, std::nullopt};
    l.share = 0.25;
    runs.push_back(l);
  }
  runs.push_back({{1e-2, std::pow(10.0, -1.5)}, std::string("b"), 1.0, std::nullopt});  // share 1
  const auto middle = compaction::server::regions::predict_at(runs, -2.0, -2.0);
  EXPECT_EQ(middle.cls, "b");
  for (auto& r : runs) r.share = 1.0;
  EXPECT_EQ(compaction::server::regions::predict_at(runs, -2.0, -2.0).cls, "a");
}
