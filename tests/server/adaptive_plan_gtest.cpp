// Adaptive sweeps: the spec's parser, the initial grid, and the planning loop driven on
// synthetic label fields over the issue's box (S in [1e-3, 1e-1], R in [1e-5, 1e-1], 5 x 5
// initial points, 1/8 decade): boundaries located to the finest step with far fewer runs than
// the full grid, the budget, pending points, spacing, order and determinism.
#include "plan/adaptive_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "input/api_error.hpp"
#include "plan/planner.hpp"

using namespace compaction::server::adaptive;
using compaction::server::ApiError;
using nlohmann::json;

namespace {

json issue_body() {
  return json::parse(R"({"S": {"min": 1e-3, "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1},
      "initial": {"S": 5, "R": 5}, "resolution_decades": 0.125, "budget": 200})");
}

AdaptiveSpec issue_spec(std::size_t budget = 200) {
  AdaptiveSpec s = parse_spec(issue_body(), 2000);
  s.budget = budget;
  return s;
}

// The full grid of the issue's box at the finest step: 2 decades of S and 4 of R at 1/8 decade.
constexpr double kStep = 0.125, kX0 = -3, kY0 = -5;
constexpr int kNodesS = 17, kNodesR = 33;
constexpr int kFullGrid = kNodesS * kNodesR;  // 561

// A synthetic classifier: the verdict at (log10 S, log10 R).
struct Verdict {
  std::optional<std::string> label;
  double confidence = 0.9;
  std::optional<std::string> runner_up;
};
using Field = std::function<Verdict(double x, double y)>;

Verdict clear(const char* label, const char* runner_up) { return {label, 0.9, runner_up}; }

Labelled run(const Field& f, Point p) {
  const Verdict v = f(std::log10(p.S), std::log10(p.R));
  return {p, v.label, v.confidence, v.runner_up};
}

// The node (i, j) of the finest lattice a point is on (every planned point is on one).
std::pair<int, int> node(Point p) {
  const double i = (std::log10(p.S) - kX0) / kStep, j = (std::log10(p.R) - kY0) / kStep;
  EXPECT_NEAR(i, std::round(i), 1e-6) << "S = " << p.S << " is off the 1/8-decade lattice";
  EXPECT_NEAR(j, std::round(j), 1e-6) << "R = " << p.R << " is off the 1/8-decade lattice";
  return {static_cast<int>(std::lround(i)), static_cast<int>(std::lround(j))};
}

bool closer_than_resolution(Point a, Point b) {
  const double r = kStep * (1 - 1e-9);
  return std::abs(std::log10(a.S) - std::log10(b.S)) < r &&
         std::abs(std::log10(a.R) - std::log10(b.R)) < r;
}

struct Drive {
  std::vector<Labelled> done;
  std::size_t asks = 0;
};

// The integration loop: `workers` points run at once; each step finishes the oldest queued
// point and asks for as many as keep `workers` queued. Checks on every proposal: not run, not
// queued, not closer than the resolution to either, within the budget.
Drive drive(const AdaptiveSpec& spec, const Field& field, std::size_t workers) {
  Drive d;
  std::vector<Point> pending;
  for (;;) {
    const std::size_t want = workers > pending.size() ? workers - pending.size() : 0;
    const std::vector<Point> next = next_points(spec, d.done, pending, want);
    ++d.asks;
    EXPECT_LE(next.size(), want);
    for (const Point& p : next) {
      for (const Labelled& l : d.done) {
        EXPECT_FALSE(closer_than_resolution(p, l.point)) << "proposed S " << p.S << " R " << p.R
                                                         << " next to a run at S " << l.point.S
                                                         << " R " << l.point.R;
      }
      for (const Point& q : pending) {
        EXPECT_FALSE(closer_than_resolution(p, q)) << "proposed S " << p.S << " R " << p.R
                                                   << " next to a queued point";
      }
    }
    for (std::size_t a = 0; a < next.size(); ++a) {
      for (std::size_t b = a + 1; b < next.size(); ++b) EXPECT_FALSE(next[a] == next[b]);
    }
    pending.insert(pending.end(), next.begin(), next.end());
    EXPECT_LE(d.done.size() + pending.size(), spec.budget);
    if (pending.empty()) break;
    d.done.push_back(run(field, pending.front()));
    pending.erase(pending.begin());
    if (d.asks > 10 * spec.budget) {
      ADD_FAILURE() << "the loop does not end";
      break;
    }
  }
  return d;
}

// The edges of the finest lattice whose ends the field labels differently and that were not
// both run: where the boundary is not located to 1/8 decade.
std::vector<std::string> unlocated(const std::vector<Labelled>& done, const Field& truth) {
  std::set<std::pair<int, int>> ran;
  for (const Labelled& l : done) ran.insert(node(l.point));
  std::vector<std::string> out;
  auto label = [&](int i, int j) { return truth(kX0 + i * kStep, kY0 + j * kStep).label; };
  for (int i = 0; i < kNodesS; ++i) {
    for (int j = 0; j < kNodesR; ++j) {
      for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
        const int i2 = i + di, j2 = j + dj;
        if (i2 >= kNodesS || j2 >= kNodesR || label(i, j) == label(i2, j2)) continue;
        if (ran.count({i, j}) && ran.count({i2, j2})) continue;
        std::ostringstream edge;
        edge << "(" << i << "," << j << ")-(" << i2 << "," << j2 << ")";
        out.push_back(edge.str());
      }
    }
  }
  return out;
}

std::string first(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t k = 0; k < v.size() && k < 8; ++k) s += v[k] + " ";
  return s;
}

// The fields. x = log10 S in [-3, -1], y = log10 R in [-5, -1]; boundaries off the lattice.
const Field straight = [](double, double y) {
  return y < -2.93 ? clear("a", "b") : clear("b", "a");
};
const Field curved = [](double x, double y) {  // a parabola from y = -4.2 to -1.4
  return y < -4.2 + 0.7 * (x + 3) * (x + 3) ? clear("a", "b") : clear("b", "a");
};
const Field three = [](double x, double y) {  // c above, a and b below, meeting at (-1.85, -2.6)
  if (y >= -2.6) return clear("c", "a");
  return x < -1.85 ? clear("a", "c") : clear("b", "a");
};
const Field island = [](double x, double y) {  // a disc of 0.3 decades holding one initial node
  const double r2 = (x + 2.1) * (x + 2.1) + (y + 3.1) * (y + 3.1);
  return r2 < 0.09 ? clear("e", "d") : clear("d", "e");
};

std::set<std::pair<double, double>> points_of(const std::vector<Labelled>& done) {
  std::set<std::pair<double, double>> s;
  for (const Labelled& l : done) s.insert({l.point.S, l.point.R});
  return s;
}

}  // namespace

// ---- the spec ----------------------------------------------------------------------------

TEST(AdaptiveSpec, TheIssuesBodyParses) {
  const AdaptiveSpec s = parse_spec(issue_body(), 2000);
  EXPECT_EQ(s.S.min, 1e-3);
  EXPECT_EQ(s.S.max, 1e-1);
  EXPECT_EQ(s.R.min, 1e-5);
  EXPECT_EQ(s.R.max, 1e-1);
  EXPECT_EQ(s.initial_S, 5);
  EXPECT_EQ(s.initial_R, 5);
  EXPECT_EQ(s.resolution_decades, 0.125);
  EXPECT_EQ(s.budget, 200u);
  EXPECT_EQ(s.in_flight, kDefaultInFlight) << "not in the body";
  json b = issue_body();
  b["in_flight"] = 32;
  EXPECT_EQ(parse_spec(b, 2000).in_flight, 32u);
  const Steps steps = finest_steps(s);
  EXPECT_DOUBLE_EQ(steps.S, 0.125) << "0.5 decade halved twice";
  EXPECT_DOUBLE_EQ(steps.R, 0.125) << "1 decade halved three times";
}

TEST(AdaptiveSpec, WhatARequestLeavesOutTakesTheServersDefaults) {
  const json box = {{"S", {{"min", 3e-3}, {"max", 3e-2}}}, {"R", {{"min", 1e-5}, {"max", 1e-2}}}};
  const AdaptiveSpec s = parse_spec(box, 2000);
  EXPECT_EQ(s.initial_S, kDefaultInitialPerAxis);
  EXPECT_EQ(s.initial_R, kDefaultInitialPerAxis);
  EXPECT_EQ(s.resolution_decades, kDefaultResolutionDecades);
  EXPECT_EQ(s.budget, static_cast<std::size_t>(kDefaultBudget));
  // Below the sweep limit the default budget is the limit, never less than the initial grid.
  EXPECT_EQ(parse_spec(box, 100).budget, 100u);
  json big = box;
  big["initial"] = {{"S", 20}, {"R", 20}};
  big["resolution_decades"] = 0.03;
  EXPECT_EQ(parse_spec(big, 2000).budget, 400u);
}

TEST(AdaptiveSpec, TheFinestStepIsTheLastHalvingNotBelowTheResolution) {
  json b = issue_body();
  b["initial"]["S"] = 6;  // 0.4 decade: 0.2 is the last halving >= 0.125
  const Steps steps = finest_steps(parse_spec(b, 2000));
  EXPECT_DOUBLE_EQ(steps.S, 0.2);
  EXPECT_DOUBLE_EQ(steps.R, 0.125);
}

TEST(AdaptiveSpec, ErrorsNameTheFieldAndTheValue) {
  struct Case {
    std::function<void(json&)> change;
    int status;
    std::string field, message_part;
  };
  const std::vector<Case> cases = {
      {[](json& b) { b = json::array(); }, 422, "adaptive", "an array of 0 values"},
      {[](json& b) { b["step"] = 1; }, 422, "adaptive.step", "unknown key"},
      {[](json& b) { b.erase("S"); }, 422, "adaptive.S", "is required"},
      {[](json& b) { b["S"] = 0.01; }, 422, "adaptive.S", "got 0.01"},
      {[](json& b) { b["S"]["scale"] = "log"; }, 422, "adaptive.S.scale", "unknown key"},
      {[](json& b) { b["S"]["min"] = 0; }, 422, "adaptive.S.min", "must be in (0, 1), got 0"},
      {[](json& b) { b["S"]["min"] = "1e-3"; }, 422, "adaptive.S.min", "\"1e-3\""},
      {[](json& b) { b["R"]["max"] = 2; }, 422, "adaptive.R.max", "got 2"},
      {[](json& b) { b["R"]["max"] = 1e-6; }, 422, "adaptive.R.max", "must be > min (1e-05), got 1e-06"},
      {[](json& b) { b["R"].erase("min"); }, 422, "adaptive.R.min", "is required"},
      {[](json& b) { b["initial"]["S"] = 1; }, 422, "adaptive.initial.S", "at least 2, got 1"},
      {[](json& b) { b["initial"]["R"] = 2.5; }, 422, "adaptive.initial.R", "got 2.5"},
      {[](json& b) { b["initial"] = {{"S", 100}, {"R", 100}}; }, 413, "adaptive.initial.S", "2000"},
      {[](json& b) { b["resolution_decades"] = 0; }, 422, "adaptive.resolution_decades", "got 0"},
      {[](json& b) { b["resolution_decades"] = 0.01; }, 422, "adaptive.resolution_decades", "0.015625"},
      {[](json& b) { b["resolution_decades"] = 0.6; }, 422, "adaptive.resolution_decades",
       "at most the initial grid's step in S (0.5 decades), got 0.6"},
      {[](json& b) { b["resolution_decades"] = "fine"; }, 422, "adaptive.resolution_decades", "\"fine\""},
      {[](json& b) { b["budget"] = 24; }, 422, "adaptive.budget", "at least 25, got 24"},
      {[](json& b) { b["budget"] = 2001; }, 413, "adaptive.budget", "sweep limit of 2000"},
      {[](json& b) { b["budget"] = 200.5; }, 422, "adaptive.budget", "must be an integer"},
      {[](json& b) { b["in_flight"] = 0; }, 422, "adaptive.in_flight", "at least 1, got 0"},
      {[](json& b) { b["in_flight"] = 201; }, 422, "adaptive.in_flight", "at most the budget (200), got 201"},
  };
  for (const Case& c : cases) {
    json b = issue_body();
    c.change(b);
    try {
      parse_spec(b, 2000);
      ADD_FAILURE() << "no error for " << b.dump();
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status, c.status) << b.dump();
      EXPECT_EQ(e.field, c.field) << b.dump();
      EXPECT_NE(std::string(e.what()).find(c.message_part), std::string::npos)
          << "message: " << e.what() << "; expected it to hold: " << c.message_part;
    }
  }
}

// ---- the initial grid --------------------------------------------------------------------

TEST(AdaptiveInitial, TheGridIsAGridSweepsLogAxesExactly) {
  const std::vector<Point> pts = initial_points(issue_spec());
  ASSERT_EQ(pts.size(), 25u);
  const auto S = compaction::server::expand_axis(
      {{"min", 1e-3}, {"max", 1e-1}, {"n", 5}, {"scale", "log"}}, "S", 100);
  const auto R = compaction::server::expand_axis(
      {{"min", 1e-5}, {"max", 1e-1}, {"n", 5}, {"scale", "log"}}, "R", 100);
  for (std::size_t j = 0; j < 5; ++j) {
    for (std::size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(pts[j * 5 + i].S, S[i]) << "R outer, S inner, the same doubles";
      EXPECT_EQ(pts[j * 5 + i].R, R[j]);
    }
  }
  EXPECT_EQ(pts.front(), (Point{1e-3, 1e-5}));
  EXPECT_EQ(pts.back(), (Point{1e-1, 1e-1}));
  EXPECT_EQ(pts[12].S, 0.01) << "10^-2 as the literal";
}

TEST(AdaptiveInitial, NextPointsStartsWithTheInitialGrid) {
  const AdaptiveSpec spec = issue_spec();
  const std::vector<Point> first = next_points(spec, {}, {}, 100);
  const std::vector<Point> grid = initial_points(spec);
  ASSERT_EQ(first.size(), grid.size());
  std::set<std::pair<double, double>> a, b;
  for (const Point& p : first) a.insert({p.S, p.R});
  for (const Point& p : grid) b.insert({p.S, p.R});
  EXPECT_EQ(a, b);
  EXPECT_EQ(first.front().S, 0.1) << "cheapest first: the largest S";
}

// ---- the loop on synthetic fields --------------------------------------------------------

// The boundary is 2 decades long; located to 1/8 decade it needs the 17 columns' two nodes on
// either side of it (34 runs) plus the coarser cells' nodes around it. A fifth of the full grid
// (112 of 561) leaves room for those and fails if the planner refines cells that hold no
// boundary.
TEST(AdaptiveLoop, AStraightBoundaryIsLocatedWithAFifthOfTheFullGrid) {
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, straight, 4);
  EXPECT_TRUE(unlocated(d.done, straight).empty()) << first(unlocated(d.done, straight));
  EXPECT_TRUE(resolved(spec, d.done));
  EXPECT_LE(d.done.size(), kFullGrid / 5) << "runs used, of a full grid of " << kFullGrid;
  EXPECT_GE(d.done.size(), 25u + 34u) << "the initial grid and the two rows along the boundary";
}

// A parabola crossing 2.8 decades of R: longer than the straight line, so a third of the full
// grid (187).
TEST(AdaptiveLoop, ACurvedBoundaryIsLocatedWithAThirdOfTheFullGrid) {
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, curved, 4);
  EXPECT_TRUE(unlocated(d.done, curved).empty()) << first(unlocated(d.done, curved));
  EXPECT_TRUE(resolved(spec, d.done));
  EXPECT_LE(d.done.size(), kFullGrid / 3);
}

// Two boundaries, one along S (2 decades at log10 R = -2.6) and one along R (2.4 decades below
// it), and the point where three regions meet: a third of the full grid (187).
TEST(AdaptiveLoop, ThreeRegionsMeetingAreLocatedWithAThirdOfTheFullGrid) {
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, three, 4);
  EXPECT_TRUE(unlocated(d.done, three).empty()) << first(unlocated(d.done, three));
  EXPECT_TRUE(resolved(spec, d.done));
  EXPECT_LE(d.done.size(), kFullGrid / 3);
  std::set<std::string> labels;
  for (const Labelled& l : d.done) labels.insert(l.label.value_or("?"));
  EXPECT_EQ(labels, (std::set<std::string>{"a", "b", "c"}));
}

// A disc 0.6 decades across around one initial node: its whole rim (about 2 decades) to 1/8
// decade, with a sixth of the full grid (93).
TEST(AdaptiveLoop, ASmallIslandOnAnInitialNodeIsOutlined) {
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, island, 4);
  EXPECT_TRUE(unlocated(d.done, island).empty()) << first(unlocated(d.done, island));
  EXPECT_TRUE(resolved(spec, d.done));
  EXPECT_LE(d.done.size(), kFullGrid / 6);
  EXPECT_GT(std::count_if(d.done.begin(), d.done.end(), [](const Labelled& l) { return l.label == "e"; }), 5)
      << "the island's interior was found";
}

// A small island on no initial node, next to the straight boundary: the split of a cell above
// finds it on the cell's lower edge, and the cell below, whose corners all agree, is split for
// that point on its edge, so the island is outlined on both sides.
TEST(AdaptiveLoop, AnIslandFoundByANeighboursSplitIsOutlinedOnBothSides) {
  const Field f = [](double x, double y) {
    const double r2 = (x + 2.25) * (x + 2.25) + (y + 3.1) * (y + 3.1);
    return r2 < 0.14 * 0.14 ? clear("e", "a") : straight(x, y);
  };
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, f, 4);
  EXPECT_TRUE(unlocated(d.done, f).empty()) << first(unlocated(d.done, f));
  EXPECT_TRUE(resolved(spec, d.done));
  const bool below = std::any_of(d.done.begin(), d.done.end(), [](const Labelled& l) {
    return l.label == "e" && std::log10(l.point.R) < -3.1;
  });
  EXPECT_TRUE(below) << "the island's part below log10 R = -3 was run";
}

// The straight boundary seen by a classifier that hesitates within 0.4 decade of it
// (confidence 0.1, runner-up the other class) and gets one node in four of that band wrong:
// the true boundary is still bracketed in every column (the wrong labels only add boundaries
// around them), inside the budget, and nothing is refined outside the two rows of initial cells
// (log10 R from -4 to -2) that hold the band.
TEST(AdaptiveLoop, LabelNoiseWithLowConfidenceStaysNearTheBoundary) {
  const double c = -2.93;
  const Field noisy = [c](double x, double y) {
    const Verdict truth = straight(x, y);
    if (std::abs(y - c) >= 0.4) return truth;
    const long long i = std::lround((x - kX0) / kStep), j = std::lround((y - kY0) / kStep);
    const bool wrong = (i * 7 + j * 13) % 4 == 0;
    const std::string& t = *truth.label;
    const std::string other = t == "a" ? "b" : "a";
    return wrong ? Verdict{other, 0.05, t} : Verdict{t, 0.1, other};
  };
  const AdaptiveSpec spec = issue_spec(200);
  const Drive d = drive(spec, noisy, 4);
  EXPECT_LE(d.done.size(), spec.budget);
  EXPECT_TRUE(unlocated(d.done, straight).empty()) << first(unlocated(d.done, straight));
  for (const Labelled& l : d.done) {
    const auto [i, j] = node(l.point);
    const bool initial = i % 4 == 0 && j % 8 == 0;
    const double y = std::log10(l.point.R);
    EXPECT_TRUE(initial || (y >= -4 - 1e-9 && y <= -2 + 1e-9))
        << "a refinement at R = " << l.point.R << ", outside the initial cells that hold the band";
  }
}

// A region whose runs fail (no label) next to a straight boundary: the failed runs are never
// proposed again, the loop ends, and the edge of the failed region is located like a boundary.
TEST(AdaptiveLoop, FailedRunsAreNotRetriedAndTheirEdgeIsLocated) {
  const Field failing = [](double x, double y) {
    return x > -1.6 ? Verdict{std::nullopt, 0, std::nullopt} : straight(x, y);
  };
  const AdaptiveSpec spec = issue_spec(400);
  const Drive d = drive(spec, failing, 4);
  EXPECT_EQ(points_of(d.done).size(), d.done.size()) << "a point was run twice";
  EXPECT_TRUE(unlocated(d.done, failing).empty()) << first(unlocated(d.done, failing));
  EXPECT_TRUE(resolved(spec, d.done));
  EXPECT_LT(d.done.size(), spec.budget) << "ended by itself, not by the budget";
}

TEST(AdaptiveLoop, ASweepWhoseRunsAllFailAsksForNothingBeyondTheInitialGrid) {
  const Field failing = [](double, double) { return Verdict{std::nullopt, 0, std::nullopt}; };
  const Drive d = drive(issue_spec(), failing, 4);
  EXPECT_EQ(d.done.size(), 25u);
}

TEST(AdaptiveLoop, AUniformMapIsResolvedByItsInitialGrid) {
  const Field uniform = [](double, double) { return clear("d", "a"); };
  const AdaptiveSpec spec = issue_spec();
  const Drive d = drive(spec, uniform, 4);
  EXPECT_EQ(d.done.size(), 25u);
  EXPECT_TRUE(resolved(spec, d.done));
}

TEST(AdaptiveLoop, TheBudgetIsSpentAndNeverExceeded) {
  const AdaptiveSpec spec = issue_spec(60);  // the curved boundary needs 150
  const Drive d = drive(spec, curved, 7);
  EXPECT_EQ(d.done.size(), 60u);
  EXPECT_FALSE(resolved(spec, d.done));
  std::vector<Point> pending;
  EXPECT_TRUE(next_points(spec, d.done, pending, 10).empty());
  // With queued points the budget counts them too.
  std::vector<Labelled> fewer(d.done.begin(), d.done.begin() + 50);
  for (std::size_t k = 50; k < 58; ++k) pending.push_back(d.done[k].point);
  EXPECT_LE(next_points(spec, fewer, pending, 10).size(), 2u);
}

// The tree is a function of the labels, so the loop ends on the same points whether one run or
// eight run at once (when the budget does not cut it short).
TEST(AdaptiveLoop, TheFinalPointsDoNotDependOnHowManyRunAtOnce) {
  const AdaptiveSpec spec = issue_spec(400);
  EXPECT_EQ(points_of(drive(spec, three, 1).done), points_of(drive(spec, three, 8).done));
}

// ---- one step ----------------------------------------------------------------------------

namespace {
std::vector<Labelled> initial_done(const AdaptiveSpec& spec, const Field& f) {
  std::vector<Labelled> done;
  for (const Point& p : initial_points(spec)) done.push_back(run(f, p));
  return done;
}
}  // namespace

TEST(AdaptiveStep, BeforeRefiningTheMapIsNotResolved) {
  const AdaptiveSpec spec = issue_spec();
  EXPECT_FALSE(resolved(spec, {}));
  EXPECT_FALSE(resolved(spec, initial_done(spec, straight)));
}

TEST(AdaptiveStep, PendingPointsAreNotProposedAgainAndTheirCellsWait) {
  const AdaptiveSpec spec = issue_spec();
  const std::vector<Labelled> done = initial_done(spec, straight);
  // The boundary (y = -2.93) crosses the row of cells between y = -3 and -2: four cells of
  // 0.5 x 1 decade, split at their midpoints: 3 x 5 nodes less the 2 x 5 corners = 17.
  const std::vector<Point> all = next_points(spec, done, {}, 1000);
  EXPECT_EQ(all.size(), 17u);
  EXPECT_TRUE(next_points(spec, done, all, 1000).empty()) << "every child waits for a result";

  const std::vector<Point> some = next_points(spec, done, {}, 3);
  const std::vector<Point> rest = next_points(spec, done, some, 1000);
  EXPECT_EQ(rest.size(), all.size() - 3);
  std::set<std::pair<double, double>> joined;
  for (const Point& p : some) joined.insert({p.S, p.R});
  for (const Point& p : rest) EXPECT_TRUE(joined.insert({p.S, p.R}).second) << "proposed twice";
  std::set<std::pair<double, double>> expected;
  for (const Point& p : all) expected.insert({p.S, p.R});
  EXPECT_EQ(joined, expected);
}

// A grid already at the finest step in S (17 columns) but with two rows 4 decades apart, and a
// boundary across S: the cell that straddles it is split in R alone, and its halves, whose lower
// corners still disagree, wait for the two queued midpoints before asking for more.
TEST(AdaptiveStep, CellsWithAQueuedCornerWaitForIt) {
  json b = issue_body();
  b["initial"] = {{"S", 17}, {"R", 2}};
  const AdaptiveSpec spec = parse_spec(b, 2000);
  const Field across = [](double x, double) { return x < -2.07 ? clear("a", "b") : clear("b", "a"); };
  const std::vector<Labelled> done = initial_done(spec, across);
  ASSERT_EQ(done.size(), 34u);
  const std::vector<Point> mid = next_points(spec, done, {}, 100);
  ASSERT_EQ(mid.size(), 2u);
  for (const Point& p : mid) EXPECT_NEAR(std::log10(p.R), -3, 1e-9);
  EXPECT_TRUE(next_points(spec, done, mid, 100).empty());
  std::vector<Labelled> more = done;
  for (const Point& p : mid) more.push_back(run(across, p));
  EXPECT_EQ(next_points(spec, more, {}, 100).size(), 4u) << "both halves split once their corners are in";
}

TEST(AdaptiveStep, APointOffTheLatticeKeepsItsNeighboursAway) {
  const AdaptiveSpec spec = issue_spec();
  const std::vector<Labelled> done = initial_done(spec, straight);
  const std::vector<Point> all = next_points(spec, done, {}, 1000);
  ASSERT_FALSE(all.empty());
  const Point target = all.front();
  const Point near{target.S * std::pow(10.0, 0.05), target.R * std::pow(10.0, -0.1)};
  const Point far{target.S * std::pow(10.0, 0.13), target.R};  // more than 1/8 decade in S
  for (const Point& p : next_points(spec, done, {near}, 1000)) EXPECT_FALSE(p == target);
  const auto with_far = next_points(spec, done, {far}, 1000);
  EXPECT_NE(std::find(with_far.begin(), with_far.end(), target), with_far.end());
}

TEST(AdaptiveStep, MostValuableFirstThenCheaperThenSmallerR) {
  const AdaptiveSpec spec = issue_spec();
  std::vector<Labelled> done = initial_done(spec, three);
  // All but three of the first round's points run: the splits they complete ask for points of
  // half their value, the three missing ones are still asked for at the first round's.
  const std::vector<Point> round = next_points(spec, done, {}, 1000);
  for (std::size_t k = 0; k + 3 < round.size(); ++k) done.push_back(run(three, round[k]));
  const std::vector<Proposal> ranked = ranked_candidates(spec, done, {});
  ASSERT_GT(ranked.size(), 10u);
  EXPECT_EQ(ranked.front().value, 2 * ranked.back().value) << "two sizes of cells compete";
  for (std::size_t k = 1; k < ranked.size(); ++k) {
    const Proposal &a = ranked[k - 1], &b = ranked[k];
    ASSERT_GE(a.value, b.value);
    if (a.value == b.value) {
      ASSERT_GE(a.point.S, b.point.S) << "at equal value the cheaper (larger S) first";
      if (a.point.S == b.point.S) {
        ASSERT_LT(a.point.R, b.point.R);
      }
    }
  }
  const std::vector<Point> one = next_points(spec, done, {}, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.front(), ranked.front().point);
}

TEST(AdaptiveStep, TheSameInputsInAnyOrderGiveTheSamePoints) {
  const AdaptiveSpec spec = issue_spec();
  std::vector<Labelled> done = initial_done(spec, curved);
  for (const Point& p : next_points(spec, done, {}, 1000)) done.push_back(run(curved, p));
  const std::vector<Point> pending = next_points(spec, done, {}, 5);
  const std::vector<Point> a = next_points(spec, done, pending, 20);
  std::vector<Labelled> reversed(done.rbegin(), done.rend());
  std::vector<Point> pending_reversed(pending.rbegin(), pending.rend());
  EXPECT_EQ(a, next_points(spec, done, pending, 20));
  EXPECT_EQ(a, next_points(spec, reversed, pending_reversed, 20));
  EXPECT_EQ(a.size(), 20u);
}

// Confidence alone: one node of a uniform map hesitates. Its cells are refined (a region of its
// runner-up may hide there), after boundaries of the same size, and it leaves the map resolved.
TEST(AdaptiveStep, LowConfidenceRefinesAroundItButDoesNotBlockResolution) {
  const AdaptiveSpec spec = issue_spec();
  const Point hesitant = initial_points(spec)[12];  // S = 0.01, R = 0.001
  const Field f = [&](double x, double y) {
    const bool here = std::abs(x + 2) < 1e-9 && std::abs(y + 3) < 1e-9;
    return here ? Verdict{"d", 0.05, "e"} : clear("d", "a");
  };
  const std::vector<Labelled> done = initial_done(spec, f);
  EXPECT_TRUE(resolved(spec, done));
  const std::vector<Proposal> ranked = ranked_candidates(spec, done, {});
  ASSERT_FALSE(ranked.empty()) << "the hesitant node's cells are split";
  // 1 decade cells, weight 0.5 x (1 - 0.05 / 0.25) = 0.4.
  EXPECT_DOUBLE_EQ(ranked.front().value, 0.4);
  for (const Proposal& p : ranked) {
    EXPECT_LE(std::abs(std::log10(p.point.S) - std::log10(hesitant.S)), 0.5 + 1e-9);
    EXPECT_LE(std::abs(std::log10(p.point.R) - std::log10(hesitant.R)), 1.0 + 1e-9);
  }
}
