// Adaptive sweeps through the real store (a SQLite file): the sweep starts with its initial
// grid, grows where results disagree as jobs end, never holds more jobs than its budget, shares
// results other sweeps have, waits for pending runs, and stops when cancelled. Results are
// given labels from a known field (label a below R = 1e-3, b above) instead of simulations, so
// that where the points must go is known.
#include "plan/adaptive_sweeps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "input/api_error.hpp"
#include "temp_dir.hpp"
#include "views/views.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

constexpr Millis t0 = 1'000'000;

StoreConfig config() {
  StoreConfig c;
  c.lease_ms = 10'000;
  c.backoff_base_ms = 1'000;
  c.engine_version = "test-1";
  return c;
}

// The issue's body, at a tiny resolution of numerics (cheap scenes; nothing is run here).
json adaptive_body(int budget, int in_flight = 8) {
  return {{"name", "map"},
          {"phi", 0.4},
          {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}},
          {"adaptive",
           {{"S", {{"min", 1e-3}, {"max", 1e-1}}},
            {"R", {{"min", 1e-5}, {"max", 1e-1}}},
            {"initial", {{"S", 5}, {"R", 5}}},
            {"resolution_decades", 0.125},
            {"budget", budget},
            {"in_flight", in_flight}}}};
}

// The field the results are labelled from: a boundary at R = 1e-3, independent of S.
std::string label_at(double R) { return std::log10(R) < -3.0 ? "a" : "b"; }

// The result of a leased job, labelled from the field.
ResultRecord labelled_result(const Lease& lease) {
  ResultRecord r;
  r.status = "ok";
  r.scene = lease.scene;
  r.engine_version = "test-1";
  r.source_revision = "abc";
  r.cls = label_at(json::parse(lease.scene)["R"].get<double>());
  r.confidence = 0.9;
  r.runner_up = *r.cls == "a" ? "b" : "a";
  r.summary = "{}";
  return r;
}

struct AdaptiveSweepsTest : ::testing::Test {
  TempDir dir;
  Store store{dir.file("jobs.db"), config()};
  PlannerLimits limits;
  AdaptiveSweeps adaptive;
  Millis now = t0;

  std::int64_t create(const json& body) {
    const SweepPlan plan = plan_sweep(body, limits);
    const CreatedSweep c = store.sweeps.create(sweep_rows(plan, "test-1"), now);
    adaptive.advance(store, limits, c.id, now);
    return c.id;
  }

  // Leases one job, completes it with the field's label and lets the sweeps that the
  // completion found holding the job plan on, as the complete route does. False when the queue
  // is empty.
  bool run_one() {
    const auto lease = store.queue.lease("w", "test-1", ++now);
    if (!lease) return false;
    QueueStore::FollowUps follow;
    EXPECT_EQ(store.queue.complete(lease->job_id, lease->token, labelled_result(*lease), ++now,
                                   std::nullopt, &follow),
              LeaseCheck::ok);
    EXPECT_EQ(follow.adaptive_sweeps, store.reads.live_adaptive_sweeps_of_job(lease->job_id));
    adaptive.advance_each(store, limits, follow.adaptive_sweeps, now);
    return true;
  }

  StateCounts counts(std::int64_t sweep) { return store.reads.sweep(sweep)->counts; }
};

}  // namespace

TEST_F(AdaptiveSweepsTest, ASweepStartsWithItsInitialGridAndGrowsWhereLabelsDifferUpToItsBudget) {
  const std::int64_t id = create(adaptive_body(60));
  EXPECT_EQ(counts(id).total(), 25) << "the initial 5 x 5 grid, nothing known yet";
  std::int64_t most = 0;
  while (run_one()) {
    const StateCounts c = counts(id);
    EXPECT_LE(c.total(), 60) << "never beyond the budget";
    EXPECT_LE(c.open(), 25) << "the initial grid, then at most in_flight queued";
    most = std::max(most, c.total());
  }
  const StateCounts c = counts(id);
  EXPECT_EQ(c.open(), 0);
  EXPECT_GT(c.total(), 25) << "it grew";
  EXPECT_LE(c.total(), 60);
  // Every point added after the grid lies on the boundary's side of the map: within an initial
  // cell (1 decade of R) of R = 1e-3, where the labels differ.
  const auto jobs = *store.reads.sweep_jobs(id);
  for (std::size_t i = 25; i < jobs.size(); ++i) {
    EXPECT_LE(std::abs(std::log10(jobs[i].R) + 3.0), 1.0 + 1e-9) << "job " << jobs[i].id;
  }
}

TEST_F(AdaptiveSweepsTest, TheBoundaryIsFoundToTheResolutionWithFewerRunsThanTheFullGrid) {
  const std::int64_t id = create(adaptive_body(400));
  while (run_one()) {
  }
  const auto jobs = *store.reads.sweep_jobs(id);
  // The full grid at 1/8 decade over 2 x 4 decades: 17 x 33 = 561 points. A straight boundary
  // across S needs a row of points on each side of it: 17 x 2 plus the initial grid and the
  // cells that lead there, far fewer.
  EXPECT_LT(jobs.size(), 561u / 3);
  // Both sides of the boundary are sampled at the finest step: a point at R = 10^-3.125 (a) and
  // one at 10^-3 (b) for every finest S.
  int below = 0, at = 0;
  for (const auto& j : jobs) {
    if (std::abs(std::log10(j.R) + 3.125) < 1e-9) ++below;
    if (std::abs(std::log10(j.R) + 3.0) < 1e-9) ++at;
  }
  EXPECT_EQ(below, 17);
  EXPECT_EQ(at, 17);
}

TEST_F(AdaptiveSweepsTest, ThePlanReportsRunsCandidatesAndTheStateAsTheSweepGoes) {
  const std::int64_t id = create(adaptive_body(400));
  auto r = AdaptiveSweeps::report(store, limits, id);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->done, 0u);
  EXPECT_EQ(r->pending, 25u);
  EXPECT_FALSE(r->resolved);
  EXPECT_TRUE(r->candidates.empty()) << "every cell has a corner still queued";
  json v = views::sweep_plan(id, *r, 20);
  EXPECT_EQ(v["state"], "running");
  // The lattice at 1/8 decade over 2 x 4 decades: the full grid of the test above.
  EXPECT_EQ(v["lattice"]["S"], 17);
  EXPECT_EQ(v["lattice"]["R"], 33);
  EXPECT_EQ(v["lattice"]["points"], 561);
  EXPECT_EQ(v["runs"]["budget_left"], 400 - 25);
  EXPECT_EQ(v["columns"], json::array()) << "no point finished: no column to report";

  // The initial grid done (its jobs run without planning): the cells across R = 1e-3 ask for
  // points, the most valuable first.
  for (int i = 0; i < 25; ++i) {
    const auto lease = store.queue.lease("w", "test-1", ++now);
    ASSERT_TRUE(lease);
    ASSERT_EQ(store.queue.complete(lease->job_id, lease->token, labelled_result(*lease), ++now),
              LeaseCheck::ok);
  }
  r = AdaptiveSweeps::report(store, limits, id);
  EXPECT_EQ(r->done, 25u);
  EXPECT_EQ(r->pending, 0u);
  EXPECT_FALSE(r->resolved) << "the labels differ across cells one decade tall";
  ASSERT_FALSE(r->candidates.empty());
  for (std::size_t i = 1; i < r->candidates.size(); ++i) {
    EXPECT_GE(r->candidates[i - 1].value, r->candidates[i].value) << "best first";
  }
  for (const auto& c : r->candidates) {
    EXPECT_LE(std::abs(std::log10(c.point.R) + 3.0), 1.0 + 1e-9) << "beside the boundary";
  }
  v = views::sweep_plan(id, *r, 2);
  EXPECT_EQ(v["state"], "planning") << "nothing pending, points worth running, budget left";
  EXPECT_EQ(v["candidates"].size(), 2u) << "the limit";
  EXPECT_EQ(v["candidates_total"], r->candidates.size());
  // Each of the initial grid's 5 S columns brackets the boundary between two of its 5 R points,
  // a decade apart: not yet the finest step (1/8 decade).
  ASSERT_EQ(v["columns"].size(), 5u);
  for (const json& c : v["columns"]) {
    EXPECT_EQ(c["points"], 5) << c;
    EXPECT_EQ(c["boundaries"], 1) << c;
    EXPECT_NEAR(c["bracket_decades"].get<double>(), 1.0, 1e-9) << c;
    EXPECT_EQ(c["resolved"], false) << c;
    EXPECT_EQ(c["finest_level"], 0) << c;
  }

  adaptive.advance(store, limits, id, now);
  while (run_one()) {
  }
  r = AdaptiveSweeps::report(store, limits, id);
  EXPECT_TRUE(r->resolved);
  EXPECT_EQ(r->pending, 0u);
  v = views::sweep_plan(id, *r, 20);
  EXPECT_EQ(v["state"], "resolved");
  // Every S of the lattice now brackets the boundary within the finest step.
  ASSERT_EQ(v["columns"].size(), 17u);
  for (const json& c : v["columns"]) {
    EXPECT_EQ(c["resolved"], true) << c;
    EXPECT_LE(c["bracket_decades"].get<double>(), 0.125 + 1e-9) << c;
  }
}

TEST_F(AdaptiveSweepsTest, ReplicatesGoWhereTheMapIsNoisyAndItsMajorityDrawsTheBoundary) {
  json body = adaptive_body(600);
  body["replicates"] = {{"n", 3}, {"perturbation", 0.01}};
  const std::int64_t id = create(body);
  EXPECT_EQ(counts(id).total(), 25) << "the initial 5 x 5 grid, one run a point";
  // A noisy field: within a quarter decade of the boundary, the replicate with seed 1 says the
  // other class (a 1 % perturbation choosing the mechanism); the majority stays the field's. The
  // seed-1 map alone has three boundaries where the field has one.
  const auto noisy = [](const Lease& lease) {
    ResultRecord r = labelled_result(lease);
    const json scene = json::parse(lease.scene);
    if (std::abs(std::log10(scene["R"].get<double>()) + 3.0) <= 0.25 && scene["seed"] == 1) {
      r.cls = *r.cls == "a" ? "b" : "a";
    }
    return r;
  };
  while (const auto lease = store.queue.lease("w", "test-1", ++now)) {
    QueueStore::FollowUps follow;
    ASSERT_EQ(store.queue.complete(lease->job_id, lease->token, noisy(*lease), ++now, std::nullopt,
                                   &follow),
              LeaseCheck::ok);
    adaptive.advance_each(store, limits, follow.adaptive_sweeps, now);
    EXPECT_LE(counts(id).total(), 600) << "the budget counts runs";
  }
  const auto jobs = *store.reads.sweep_jobs(id);
  std::map<std::pair<double, double>, std::set<std::uint64_t>> seeds;
  for (const auto& j : jobs) seeds[{j.S, j.R}].insert(json::parse(j.scene)["seed"].get<std::uint64_t>());
  std::size_t replicated = 0;
  for (const auto& [at, s] : seeds) {
    EXPECT_TRUE(s == (std::set<std::uint64_t>{1}) || s == (std::set<std::uint64_t>{1, 2}) ||
                s == (std::set<std::uint64_t>{1, 2, 3}))
        << "seeds in order";
    if (s.size() > 1) {
      ++replicated;
      // The noisy rows are 10^-3.25 to 10^-2.75; the seed-1 map's boundaries lie beside them.
      EXPECT_LE(std::abs(std::log10(at.second) + 3.0), 0.375 + 1e-9) << "replicates only near the noise";
    }
  }
  EXPECT_GT(replicated, 0u);
  const auto r = AdaptiveSweeps::report(store, limits, id);
  EXPECT_EQ(r->replicates, 3u);
  EXPECT_EQ(r->done, jobs.size());
  EXPECT_TRUE(r->resolved) << "the majority draws the field's boundary, noise and all";
  const json plan = views::sweep_plan(id, *r, 5);
  EXPECT_EQ(plan["replicates"], 3);
  EXPECT_EQ(plan["lattice"]["runs"], 561 * 3);
  EXPECT_EQ(plan["state"], "resolved");
  ASSERT_EQ(plan["levels"].size(), 1u);
  EXPECT_EQ(plan["levels"][0]["runs"]["done"], jobs.size());
  const json map = json::parse(views::phase_map(0.4, store.reads.phase_map(0.4, id)));
  std::size_t robust = 0;
  for (const json& pt : map["summaries"]) robust += pt["robust"] == true;
  EXPECT_EQ(plan["levels"][0]["robust"], robust);
  // The map: every replicated point reads the field's label by its majority, and for every S
  // the two points beside the boundary (R = 10^-3.125 and 10^-3) have their three runs.
  std::set<double> below, at;
  for (const json& pt : map["summaries"]) {
    if (pt["runs"] == 3) {
      EXPECT_EQ(pt["label"], label_at(pt["R"].get<double>())) << pt.dump();
    }
    const double lr = std::log10(pt["R"].get<double>());
    if (std::abs(lr + 3.125) < 1e-9 && pt["runs"] == 3) below.insert(pt["S"].get<double>());
    if (std::abs(lr + 3.0) < 1e-9 && pt["runs"] == 3) at.insert(pt["S"].get<double>());
  }
  EXPECT_EQ(below.size(), 17u);
  EXPECT_EQ(at.size(), 17u);
}

TEST_F(AdaptiveSweepsTest, LevelsRunTheFinerNumericsAlongTheBoundary) {
  json body = adaptive_body(1000);
  body["adaptive"]["levels"] = json::parse(R"([{"cells_per_unit": 6}, {"cells_per_unit": 10}])");
  body["adaptive"]["budget_cpu_hours"] = 1000;
  const std::int64_t id = create(body);
  while (run_one()) {
  }
  const auto jobs = *store.reads.sweep_jobs(id);
  std::size_t fine = 0;
  for (const auto& j : jobs) {
    ASSERT_TRUE(j.cells_per_unit == 6 || j.cells_per_unit == 10) << j.cells_per_unit;
    if (j.cells_per_unit == 10) {
      ++fine;
      EXPECT_LE(std::abs(std::log10(j.R) + 3.0), 0.25 + 1e-9) << "the finer level beside the boundary";
    }
  }
  EXPECT_EQ(fine, 2u * 17u) << "both sides of the boundary, every finest S";
  const auto r = AdaptiveSweeps::report(store, limits, id);
  EXPECT_TRUE(r->resolved);
  const json plan = views::sweep_plan(id, *r, 5);
  ASSERT_EQ(plan["levels"].size(), 2u);
  EXPECT_EQ(plan["levels"][0]["cells_per_unit"], 6);
  EXPECT_EQ(plan["levels"][1]["cells_per_unit"], 10);
  EXPECT_EQ(plan["levels"][1]["runs"]["done"], fine);
  EXPECT_EQ(plan["levels"][1]["points"], fine);
  EXPECT_GT(plan["cpu_hours"]["spent"].get<double>(), 0.0);
  EXPECT_EQ(plan["cpu_hours"]["budget"], 1000.0);
}

TEST_F(AdaptiveSweepsTest, ThePlanOfAGridSweepIsRefusedAndOfNoSweepIsNone) {
  json grid = adaptive_body(60);
  grid.erase("adaptive");
  grid["S"] = 1e-2;
  grid["R"] = 1e-3;
  const SweepPlan plan = plan_sweep(grid, limits);
  const std::int64_t id = store.sweeps.create(sweep_rows(plan, "test-1"), now).id;
  try {
    AdaptiveSweeps::report(store, limits, id);
    ADD_FAILURE() << "a grid sweep has no plan";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 409);
    EXPECT_EQ(e.field, "id");
  }
  EXPECT_FALSE(AdaptiveSweeps::report(store, limits, id + 100));
}

TEST_F(AdaptiveSweepsTest, PointsOtherSweepsHaveResultsForAreKnownAtOnceAndPlannedPast) {
  const std::int64_t first = create(adaptive_body(80));
  while (run_one()) {
  }
  const std::int64_t n_first = counts(first).total();
  // The same map again: every point the first sweep ran is reused, so the second plans past
  // them without a single run, to the same points.
  const std::int64_t second = create(adaptive_body(80));
  EXPECT_EQ(counts(second).total(), n_first);
  EXPECT_EQ(counts(second).open(), 0);
  EXPECT_FALSE(run_one()) << "nothing to run";
}

TEST_F(AdaptiveSweepsTest, ACancelledSweepDoesNotGrow) {
  const std::int64_t id = create(adaptive_body(200));
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(run_one());
  ASSERT_TRUE(store.sweeps.cancel(id, ++now));
  const std::int64_t total = counts(id).total();
  EXPECT_EQ(adaptive.advance(store, limits, id, ++now), 0u);
  EXPECT_EQ(counts(id).total(), total);
}

TEST_F(AdaptiveSweepsTest, AGridSweepIsNeverAdvanced) {
  const SweepPlan plan = plan_sweep(
      {{"name", "grid"}, {"S", {0.01, 0.1}}, {"R", {1e-5, 1e-1}}, {"phi", 0.4},
       {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}},
      limits);
  const CreatedSweep c = store.sweeps.create(sweep_rows(plan, "test-1"), now);
  while (run_one()) {
  }
  EXPECT_EQ(adaptive.advance(store, limits, c.id, ++now), 0u);
  EXPECT_EQ(counts(c.id).total(), 4);
}

TEST_F(AdaptiveSweepsTest, AtStartEveryLiveAdaptiveSweepPlansOn) {
  // Results stored without planning (the server stopped in between): the sweep would wait
  // forever for results that will not come.
  const SweepPlan plan = plan_sweep(adaptive_body(60), limits);
  const CreatedSweep c = store.sweeps.create(sweep_rows(plan, "test-1"), now);
  while (const auto lease = store.queue.lease("w", "test-1", ++now)) {
    ASSERT_EQ(store.queue.complete(lease->job_id, lease->token, labelled_result(*lease), ++now),
              LeaseCheck::ok);
  }
  ASSERT_EQ(counts(c.id).open(), 0);
  adaptive.advance_all(store, limits, ++now);
  EXPECT_GT(counts(c.id).open(), 0) << "new points queued";
  EXPECT_LE(counts(c.id).open(), 8) << "at most in_flight";
}
