// The resolution an adaptive sweep reached per S column (plan/column_resolution.hpp): on points
// placed by hand on the lattice of issue 47's trusted box (9 x 25 nodes, an eighth of a decade),
// the brackets, boundaries, unknown labels, levels and points off the lattice; on a sweep driven
// to its end over a synthetic field (levels_plan_gtest's kind), every column resolved.
#include "plan/column_resolution.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "trusted_box.hpp"

namespace compaction::server::adaptive {
namespace {

NodeLabel at(const LevelsSpec& s, long long i, long long j, std::optional<std::string> label,
             int level = 0) {
  NodeLabel n;
  n.point = *lattice_point(s.box, {i, j});
  n.level = level;
  n.tally.label = std::move(label);
  return n;
}

TEST(ColumnResolution, BracketsBoundariesAlongRPerColumn) {
  const LevelsSpec s = trusted_spec(2, 4, 400);
  ASSERT_NEAR(finest_steps(s.box).R, 0.125, 1e-12);
  std::vector<NodeLabel> nodes = {
      // Column 0: the initial grid's points only, a boundary between R = 1e-4 and 1e-3.
      at(s, 0, 24, "b"), at(s, 0, 0, "a"), at(s, 0, 16, "b"), at(s, 0, 8, "a"),
      // Column 8: bracketed to the finest step, then a failed point beside a label.
      at(s, 8, 10, "a", 1), at(s, 8, 11, "b"), at(s, 8, 12, std::nullopt),
      // Column 4: one label all along.
      at(s, 4, 0, "a"), at(s, 4, 24, "a"),
  };
  NodeLabel off;  // a point of another sweep, off the lattice
  off.point = {0.005, 2e-4};
  off.tally.label = "c";
  nodes.push_back(off);
  const auto cols = column_resolution(s, nodes);
  ASSERT_EQ(cols.size(), 3u);
  EXPECT_DOUBLE_EQ(cols[0].S, 3e-3);
  EXPECT_EQ(cols[0].points, 4u);
  EXPECT_EQ(cols[0].boundaries, 1u);
  ASSERT_TRUE(cols[0].bracket_decades);
  EXPECT_NEAR(*cols[0].bracket_decades, 1.0, 1e-9);
  EXPECT_FALSE(cols[0].resolved);
  EXPECT_EQ(cols[0].finest_level, 0);

  EXPECT_EQ(cols[1].points, 2u);
  EXPECT_EQ(cols[1].boundaries, 0u);
  EXPECT_FALSE(cols[1].bracket_decades);
  EXPECT_TRUE(cols[1].resolved) << "no boundary to bracket";

  EXPECT_NEAR(cols[2].S, 3e-2, 1e-14);
  EXPECT_EQ(cols[2].points, 3u);
  EXPECT_EQ(cols[2].boundaries, 2u) << "a | b, and b beside an unknown";
  EXPECT_NEAR(*cols[2].bracket_decades, 0.125, 1e-9);
  EXPECT_TRUE(cols[2].resolved);
  EXPECT_EQ(cols[2].finest_level, 1);
}

// The field of levels_plan_gtest: (a) below a line that rises 0.3 decade at the finer level.
double line(double S, int level) { return -3.0 + 0.5 * (std::log10(S) + 2.0) + 0.3 * level; }
double cost(Point p, int level) { return 0.01 / p.S * std::pow(6.0, level); }

TEST(ColumnResolution, ASweepRunToItsEndIsResolvedInEveryColumnAtTheFinestLevel) {
  const LevelsSpec s = trusted_spec(2, 4, 400);
  std::vector<LevelRun> done;
  // The initial grid alone: every column of it brackets the line within the initial R step.
  for (int round = 0; round < 1000; ++round) {
    const auto next = next_level_actions(s, done, {}, cost, 8);
    if (next.empty()) break;
    for (const LevelAction& a : next) {
      const std::string label = std::log10(a.point.R) < line(a.point.S, a.level) ? "a" : "b";
      done.push_back({a.point, a.level, label, 0.9, label == "a" ? "b" : "a"});
    }
    if (round == 0) {
      for (const ColumnResolution& c : column_resolution(s, node_labels(s, done))) {
        EXPECT_EQ(c.boundaries, 1u) << c.S;
        EXPECT_NEAR(*c.bracket_decades, 1.0, 1e-9) << c.S;
        EXPECT_FALSE(c.resolved);
      }
    }
  }
  ASSERT_TRUE(levels_resolved(s, done, cost));
  const auto cols = column_resolution(s, node_labels(s, done));
  ASSERT_EQ(cols.size(), 9u) << "every S of the lattice";
  for (const ColumnResolution& c : cols) {
    EXPECT_TRUE(c.resolved) << c.S;
    EXPECT_EQ(c.boundaries, 1u) << c.S;
    EXPECT_NEAR(*c.bracket_decades, 0.125, 1e-9) << c.S;
    EXPECT_EQ(c.finest_level, 1) << c.S;
  }
}

}  // namespace
}  // namespace compaction::server::adaptive
