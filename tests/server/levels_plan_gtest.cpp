// The levels planner (plan/levels_plan.hpp) on synthetic fields whose boundary moves with the
// level and is noisy near it, as the project's studies found the map to be: example (b)'s
// mechanism chosen by a 1 % perturbation, labels near example (c) changing with resolution.
// Runs are "computed" by the field, so where the planner must go is known exactly.
#include "plan/levels_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "trusted_box.hpp"

namespace compaction::server::adaptive {
namespace {

// A run costs about 1/S; each level 6 times the one before ((8 / 4.5)^3, the default preset
// against 8 cells across a strut).
double cost(Point p, int level) { return 0.01 / p.S * std::pow(6.0, level); }

// The field: (a) below the line log10 R = -3 + 0.5 (log10 S + 2) + shift(level), (b) above;
// the finer level's line 0.3 decade higher (more than two finest steps). Within 0.1 decade of
// the line, the run with seed 1 says the other class (its perturbation decides), with a
// confidence of 0.5; elsewhere every seed gives the field's class with 0.9.
double line(double S, int level) { return -3.0 + 0.5 * (std::log10(S) + 2.0) + 0.3 * level; }
std::string truth(Point p, int level) { return std::log10(p.R) < line(p.S, level) ? "a" : "b"; }
LevelRun compute(const LevelAction& a) {
  const bool near = std::abs(std::log10(a.point.R) - line(a.point.S, a.level)) < 0.1;
  std::string label = truth(a.point, a.level);
  if (near && a.replicate == 0) label = label == "a" ? "b" : "a";
  return {a.point, a.level, label, near ? 0.5 : 0.9, label == "a" ? "b" : "a"};
}

struct Sweep {
  explicit Sweep(LevelsSpec s) : spec(std::move(s)) {}

  LevelsSpec spec;
  std::vector<LevelRun> done;
  double cpu = 0;
  std::size_t rounds = 0;

  // Runs batches of in_flight actions until the planner has nothing left.
  void run() {
    while (true) {
      const auto next = next_level_actions(spec, done, {}, cost, spec.box.in_flight);
      if (next.empty()) return;
      for (const LevelAction& a : next) {
        done.push_back(compute(a));
        cpu += cost(a.point, a.level);
      }
      ++rounds;
      ASSERT_LT(rounds, 10000u);
    }
  }
};

TEST(LevelsPlan, FindsTheFinestLevelsBoundaryAtAQuarterOfTheBruteForceCost) {
  Sweep sw{trusted_spec(2, 4, 2000)};
  sw.run();
  EXPECT_TRUE(levels_resolved(sw.spec, sw.done, cost));
  // The brute force: every lattice node at the finest level with all replicates.
  double brute = 0;
  for (long long i = 0; i <= 8; ++i) {
    for (long long j = 0; j <= 24; ++j) brute += 4 * cost(*lattice_point(sw.spec.box, {i, j}), 1);
  }
  EXPECT_LE(sw.cpu, brute / 4) << "spent " << sw.cpu << " of a brute force of " << brute;
  // For every S of the lattice, the finest level's boundary is bracketed by two nodes one
  // finest step apart, each run 4 times at the finest level, whose majorities are the field's.
  std::map<std::pair<double, double>, std::map<int, std::vector<std::string>>> labels;
  for (const LevelRun& r : sw.done) labels[{r.point.S, r.point.R}][r.level].push_back(*r.label);
  const auto majority = [](const std::vector<std::string>& v) {
    std::map<std::string, int> n;
    for (const auto& l : v) ++n[l];
    return n["a"] > n["b"] ? "a" : "b";
  };
  for (long long i = 0; i <= 8; ++i) {
    long long below = -1;
    for (long long j = 0; j < 24; ++j) {
      const Point lo = *lattice_point(sw.spec.box, {i, j}), up = *lattice_point(sw.spec.box, {i, j + 1});
      if (truth(lo, 1) == "a" && truth(up, 1) == "b") below = j;
    }
    ASSERT_GE(below, 0) << "the field crosses every column";
    for (long long j : {below, below + 1}) {
      const Point p = *lattice_point(sw.spec.box, {i, j});
      const auto& at = labels[{p.S, p.R}][1];
      ASSERT_EQ(at.size(), 4u) << "node (" << i << ", " << j << ") at the finest level";
      EXPECT_EQ(majority(at), truth(p, 1)) << "node (" << i << ", " << j << ")";
    }
  }
  // The points between the two levels' lines changed label, and say so.
  std::size_t changed = 0;
  for (const NodeLabel& n : node_labels(sw.spec, sw.done)) {
    if (n.changed) {
      ++changed;
      EXPECT_EQ(truth(n.point, 0), "b");
      EXPECT_EQ(truth(n.point, 1), "a");
      EXPECT_EQ(n.level, 1);
    }
  }
  EXPECT_GE(changed, 9u) << "at least one per column: the line moved by two finest steps";
}

TEST(LevelsPlan, TheCoarsestMapComesFirstAndOneRunAPoint) {
  const LevelsSpec spec = trusted_spec(2, 4, 2000);
  const auto first = ranked_level_actions(spec, {}, {}, cost);
  ASSERT_EQ(first.size(), 12u) << "the initial 3 x 4 grid";
  for (const LevelAction& a : first) {
    EXPECT_EQ(a.level, 0);
    EXPECT_EQ(a.replicate, 0u);
    EXPECT_STREQ(a.why, "map");
  }
}

TEST(LevelsPlan, ABoundaryPointGetsItsReplicatesThenTheNextLevel) {
  // One finest cell across the coarse line, the rest of the map agreeing: its corners get
  // replicates 2..4 at level 0 before any of them runs at level 1.
  LevelsSpec spec = trusted_spec(2, 4, 2000);
  Sweep sw{spec};
  sw.run();
  std::map<std::tuple<double, double, int>, std::size_t> runs;
  for (const LevelRun& r : sw.done) ++runs[{r.point.S, r.point.R, r.level}];
  for (const auto& [key, n] : runs) EXPECT_LE(n, 4u) << "never beyond n replicates";
  // Every point run at level 1 was run 4 times at level 0 first, or was reached by following
  // the moved boundary (then it has no level-0 run at all or is a corner of a mixed cell).
  std::size_t promoted = 0;
  for (const auto& [key, n] : runs) {
    const auto [S, R, level] = key;
    if (level != 1) continue;
    const auto coarse = runs.find({S, R, 0});
    if (coarse != runs.end() && coarse->second == 4) ++promoted;
  }
  EXPECT_GT(promoted, 0u);
}

TEST(LevelsPlan, TheBudgetsInRunsAndInCpuSecondsAreNeverExceeded) {
  Sweep runs_limited{trusted_spec(2, 4, 60)};
  runs_limited.run();
  EXPECT_LE(runs_limited.done.size(), 60u);
  EXPECT_EQ(runs_limited.done.size(), 60u) << "spent to the last run";

  LevelsSpec cpu = trusted_spec(2, 4, 2000);
  cpu.budget_cpu_seconds = 100;
  Sweep cpu_limited{cpu};
  cpu_limited.run();
  EXPECT_LE(cpu_limited.cpu, 100.0);
  EXPECT_FALSE(levels_resolved(cpu_limited.spec, cpu_limited.done, cost));
}

TEST(LevelsPlan, OneLevelWithReplicatesMakesTheBoundaryRobust) {
  Sweep sw{trusted_spec(1, 3, 2000)};
  sw.run();
  EXPECT_TRUE(levels_resolved(sw.spec, sw.done, cost));
  for (const LevelRun& r : sw.done) EXPECT_EQ(r.level, 0);
  // Each boundary point has its 3 replicates and its majority is the field's.
  for (const NodeLabel& n : node_labels(sw.spec, sw.done)) {
    EXPECT_EQ(n.tally.label, truth(n.point, 0)) << n.point.S << " " << n.point.R;
    EXPECT_FALSE(n.changed);
  }
}

TEST(LevelsPlan, PendingRunsAreNeverAskedForTwice) {
  const LevelsSpec spec = trusted_spec(2, 4, 2000);
  const auto first = next_level_actions(spec, {}, {}, cost, 12);
  std::vector<LevelQueued> queued;
  for (const auto& a : first) queued.push_back({a.point, a.level});
  EXPECT_TRUE(next_level_actions(spec, {}, queued, cost, 12).empty())
      << "every cell has a corner still queued";
}

}  // namespace
}  // namespace compaction::server::adaptive
