// Adaptive sweeps as the server runs them: when one is created, whenever one of its jobs ends,
// and at start, the adaptive planner (adaptive_plan.hpp) is asked where to run next, and the
// runs it proposes join the sweep as jobs: the levels planner (levels_plan.hpp) over the
// sweep's levels of numerics (one without "levels") and its replicates (one without them), so
// that an adaptive sweep without either plans as adaptive_plan.hpp alone does. The budget and
// in_flight count runs. The sweep's stored request is the one home of its
// box, budget and numerics; its jobs' states and labels are what the planner reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "plan/adaptive_plan.hpp"
#include "plan/column_resolution.hpp"
#include "plan/planner.hpp"
#include "store/clock.hpp"
#include "store/store.hpp"

namespace compaction::server {

// One level of numerics of an adaptive sweep as it stands: its grid, the points run at it and
// how many of them are robust (point_tally.hpp), its runs, and what the planner would queue
// next at it (the next in_flight runs) with the cost model's CPU seconds.
struct LevelReport {
  std::int64_t cells_per_unit = 0;
  std::size_t points = 0, robust = 0;
  std::size_t runs_done = 0, runs_pending = 0;
  double cpu_seconds_done = 0, cpu_seconds_pending = 0;
  std::size_t next_runs = 0;
  double next_cpu_seconds = 0;
};

// What the planner sees of an adaptive sweep now (GET /api/v1/sweeps/{id}/plan).
struct PlanReport {
  adaptive::AdaptiveSpec spec;  // as requested: its budget and in_flight count runs
  std::size_t replicates = 1;   // the most runs of a point at one level
  double budget_cpu_seconds = 0;  // infinite without one
  std::size_t done = 0;     // finished runs: succeeded, failed for good or cancelled
  std::size_t pending = 0;  // queued or running
  double cpu_seconds = 0;   // the cost model's, of the runs done and pending
  bool cancelled = false;
  bool resolved = false;    // adaptive::levels_resolved over the finished runs
  std::vector<adaptive::LevelAction> candidates;  // every run worth queueing now, best first
  std::vector<LevelReport> levels;                // coarse to fine
  std::vector<adaptive::ColumnResolution> columns;  // per S of the lattice, its boundaries
};

class AdaptiveSweeps {
 public:
  // Queues the next points of the sweep when it is adaptive and not cancelled: as many as its
  // in_flight allows past those queued or running, never beyond its budget. Points whose result
  // another sweep already has are known at once, so it plans again until it has to wait for a
  // run. Returns the jobs added.
  std::size_t advance(Store& store, const PlannerLimits& limits, std::int64_t sweep_id, Millis now);
  // advance() for every live adaptive sweep that holds the job (it succeeded or failed for good).
  void job_ended(Store& store, const PlannerLimits& limits, std::int64_t job_id, Millis now);
  // advance() for each of these sweeps (a completion's transaction found them holding its job);
  // returns the jobs added.
  std::size_t advance_each(Store& store, const PlannerLimits& limits,
                    const std::vector<std::int64_t>& sweep_ids, Millis now);
  // advance() for every live adaptive sweep: at start (a result may have been stored just before
  // the server stopped) and after leases expire (a job may have failed for good).
  void advance_all(Store& store, const PlannerLimits& limits, Millis now);
  // The sweep's plan as the next advance() would see it; nullopt for no such sweep, ApiError
  // 409 (field "id") for a sweep that is not adaptive.
  static std::optional<PlanReport> report(Store& store, const PlannerLimits& limits,
                                          std::int64_t sweep_id);

 private:
  void plan_more(Store& store, const PlannerLimits& limits, std::int64_t sweep_id, Millis now,
                 std::size_t& added);

  // One planning at a time: two results arriving together must not both spend the budget.
  std::mutex mutex_;
};

}  // namespace compaction::server
