// A point's replicates read together (plan/point_tally.hpp): the counts are exact, so the
// shares and means are compared to 1e-12 (round-off of a few additions).
#include "plan/point_tally.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace compaction::server {
namespace {

using adaptive::Labelled;
using adaptive::Point;

const Point kAt{0.01, 1e-4};

Labelled run(std::optional<std::string> label, double confidence = 0.8,
             std::optional<std::string> runner_up = std::nullopt) {
  return {kAt, std::move(label), confidence, std::move(runner_up)};
}

TEST(PointTally, OneRunReadsAsThatRun) {
  const Tally t = tally(kAt, {run("b", 0.62, "a")}, 1);
  EXPECT_EQ(t.runs, 1u);
  EXPECT_EQ(t.labelled, 1u);
  EXPECT_EQ(t.label, "b");
  EXPECT_DOUBLE_EQ(t.share, 1.0);
  EXPECT_FALSE(t.robust);  // one run has no evidence either way
  EXPECT_EQ(t.as_run.label, "b");
  EXPECT_NEAR(t.as_run.confidence, 0.62, 1e-12);
  EXPECT_EQ(t.as_run.runner_up, "a");
  ASSERT_EQ(t.probabilities.size(), 1u);
  EXPECT_EQ(t.probabilities[0].first, "b");
}

TEST(PointTally, TheMajorityWithItsShareAndTheProbabilities) {
  const Tally t = tally(kAt, {run("a", 0.9), run("b", 0.3), run("a", 0.7), run("a", 0.8)}, 4);
  EXPECT_EQ(t.label, "a");
  EXPECT_NEAR(t.share, 0.75, 1e-12);
  EXPECT_FALSE(t.robust);
  ASSERT_EQ(t.probabilities.size(), 2u);
  EXPECT_EQ(t.probabilities[0].first, "a");
  EXPECT_NEAR(t.probabilities[0].second, 0.75, 1e-12);
  EXPECT_EQ(t.probabilities[1].first, "b");
  EXPECT_NEAR(t.probabilities[1].second, 0.25, 1e-12);
  // share 0.75 x the majority's mean confidence 0.8; the runner-up the other class seen
  EXPECT_NEAR(t.as_run.confidence, 0.6, 1e-12);
  EXPECT_EQ(t.as_run.runner_up, "b");
}

TEST(PointTally, AgreeingReplicatesAreRobustAndKeepTheirRunnerUp) {
  const Tally t = tally(kAt, {run("d", 0.5, "f"), run("d", 0.7, "f"), run("d", 0.6, "e")}, 3);
  EXPECT_TRUE(t.robust);
  EXPECT_NEAR(t.share, 1.0, 1e-12);
  EXPECT_NEAR(t.as_run.confidence, 0.6, 1e-12);
  EXPECT_EQ(t.as_run.runner_up, "f");
}

TEST(PointTally, ATieGoesToTheMoreConfidentClassThenTheEarlier) {
  const Tally higher = tally(kAt, {run("a", 0.2), run("b", 0.9), run("a", 0.3), run("b", 0.8)}, 4);
  EXPECT_EQ(higher.label, "b");
  EXPECT_NEAR(higher.share, 0.5, 1e-12);
  EXPECT_EQ(higher.as_run.runner_up, "a");
  const Tally equal = tally(kAt, {run("c", 0.5), run("b", 0.5)}, 2);
  EXPECT_EQ(equal.label, "b");
}

TEST(PointTally, PendingAndUnlabelledRunsAreNotRobustAndNotCounted) {
  // Two of four replicates finished and agree: not yet robust.
  const Tally pending = tally(kAt, {run("a"), run("a")}, 4);
  EXPECT_EQ(pending.runs, 4u);
  EXPECT_EQ(pending.finished, 2u);
  EXPECT_NEAR(pending.share, 1.0, 1e-12);
  EXPECT_FALSE(pending.robust);
  // A failed replicate (no label) leaves the share over the labelled runs, but is not robust.
  const Tally failed = tally(kAt, {run("a"), run(std::nullopt), run("a")}, 3);
  EXPECT_EQ(failed.labelled, 2u);
  EXPECT_NEAR(failed.share, 1.0, 1e-12);
  EXPECT_FALSE(failed.robust);
  // No label at all: the point is unknown, as a failed run is.
  const Tally none = tally(kAt, {run(std::nullopt)}, 2);
  EXPECT_FALSE(none.label);
  EXPECT_FALSE(none.as_run.label);
  EXPECT_TRUE(none.probabilities.empty());
}

TEST(PointSpread, MeanSampleDeviationAndCount) {
  EXPECT_FALSE(spread({}));
  const auto one = spread({2.5});
  ASSERT_TRUE(one);
  EXPECT_DOUBLE_EQ(one->mean, 2.5);
  EXPECT_FALSE(one->sd);
  // 1, 2, 3, 4: mean 2.5, sample variance 5/3
  const auto four = spread({1, 2, 3, 4});
  ASSERT_TRUE(four && four->sd);
  EXPECT_EQ(four->n, 4u);
  EXPECT_NEAR(four->mean, 2.5, 1e-12);
  EXPECT_NEAR(*four->sd, std::sqrt(5.0 / 3.0), 1e-12);
}

}  // namespace
}  // namespace compaction::server
