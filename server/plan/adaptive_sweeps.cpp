#include "plan/adaptive_sweeps.hpp"

#include <algorithm>
#include <map>

#include <spdlog/spdlog.h>

#include "input/api_error.hpp"
#include "plan/counted_label.hpp"
#include "plan/point_tally.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// The sweep's runs as the levels planner reads them: each job at its level (found by its grid
// cells per unit cell, distinct per level) with its counted label (counted_label.hpp), or queued.
struct SweepRuns {
  std::vector<adaptive::LevelRun> done;
  std::vector<adaptive::LevelQueued> pending;
};

SweepRuns split_runs(const SweepPlan& plan, const std::vector<JobRecord>& jobs) {
  std::map<std::int64_t, int> level_of;  // cells per unit cell -> level
  for (int level = 0; level < static_cast<int>(plan.levels.size()); ++level) {
    const SceneParams p = level_scene(plan, level, {plan.adaptive->S.max, plan.adaptive->R.max});
    level_of[p.grid_cells_per_unit()] = level;
  }
  SweepRuns out;
  for (const JobRecord& j : jobs) {
    const auto level = level_of.find(j.cells_per_unit);
    if (level == level_of.end()) continue;  // not a run of this sweep's levels
    const adaptive::Point pt{j.S, j.R};
    if (j.state == "queued" || j.state == "running") {
      out.pending.push_back({pt, level->second});
      continue;
    }
    if (j.state != "succeeded") {  // failed and cancelled: unknown
      out.done.push_back({pt, level->second, std::nullopt, 0.0, std::nullopt});
      continue;
    }
    // The classifier's label is none for an unstable or unclassified run.
    const std::optional<std::string> human =
        j.human_label ? std::optional<std::string>(j.human_label->label) : std::nullopt;
    const auto& r = j.result;
    const adaptive::Labelled l = counted_label(pt, human, r ? r->cls : std::nullopt,
                                               r ? r->confidence : std::nullopt,
                                               r ? r->runner_up : std::nullopt);
    out.done.push_back({pt, level->second, l.label, l.confidence, l.runner_up});
  }
  return out;
}

// An adaptive sweep as the planner reads it: its plan from the stored request and its runs.
struct SweepState {
  SweepPlan plan;
  bool cancelled = false;
  SweepRuns runs;
};

// nullopt for no such sweep or one that is not adaptive; ApiError from plan_sweep when the
// request no longer plans under the server's limits.
std::optional<SweepState> load(Store& store, const PlannerLimits& limits, std::int64_t sweep_id) {
  const auto sweep = store.reads.sweep(sweep_id);
  if (!sweep) return std::nullopt;
  const json request = json::parse(sweep->request);
  if (!request.contains("adaptive")) return std::nullopt;
  SweepState s;
  s.plan = plan_sweep(request, limits);
  s.cancelled = sweep->cancelled_at.has_value();
  const auto jobs = store.reads.sweep_jobs(sweep_id);
  if (!jobs) return std::nullopt;
  s.runs = split_runs(s.plan, *jobs);
  return s;
}

adaptive::RunCost cost_of(const SweepPlan& plan) {
  return [&plan](adaptive::Point p, int level) { return run_cpu_seconds(plan, p, level); };
}

// Per level: the points run, those robust, the runs queued and what the planner would run next.
std::vector<LevelReport> level_reports(const SweepState& s, const std::vector<adaptive::LevelAction>& next) {
  std::vector<LevelReport> out(s.plan.levels.size());
  const adaptive::RunCost cost = cost_of(s.plan);
  std::map<std::pair<int, std::pair<double, double>>, std::vector<adaptive::Labelled>> finished;
  for (const adaptive::LevelRun& r : s.runs.done) {
    LevelReport& l = out.at(static_cast<std::size_t>(r.level));
    ++l.runs_done;
    l.cpu_seconds_done += cost(r.point, r.level);
    finished[{r.level, {r.point.S, r.point.R}}].push_back({r.point, r.label, r.confidence, r.runner_up});
  }
  for (const adaptive::LevelQueued& q : s.runs.pending) {
    LevelReport& l = out.at(static_cast<std::size_t>(q.level));
    ++l.runs_pending;
    l.cpu_seconds_pending += cost(q.point, q.level);
  }
  for (const auto& [key, runs] : finished) {
    LevelReport& l = out.at(static_cast<std::size_t>(key.first));
    ++l.points;
    if (tally(runs.front().point, runs, runs.size()).robust) ++l.robust;
  }
  for (const adaptive::LevelAction& a : next) {
    LevelReport& l = out.at(static_cast<std::size_t>(a.level));
    ++l.next_runs;
    l.next_cpu_seconds += a.cpu_seconds;
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].cells_per_unit = level_scene(s.plan, static_cast<int>(i), {s.plan.adaptive->S.max, s.plan.adaptive->R.max}).grid_cells_per_unit();
  return out;
}

}  // namespace

std::optional<PlanReport> AdaptiveSweeps::report(Store& store, const PlannerLimits& limits,
                                                 std::int64_t sweep_id) {
  const auto sweep = store.reads.sweep(sweep_id);
  if (!sweep) return std::nullopt;
  std::optional<SweepState> s;
  try {
    s = load(store, limits, sweep_id);
  } catch (const ApiError& e) {
    throw ApiError(409, "id", "the sweep's request no longer plans under this server's limits (" +
                                  e.field + ": " + e.what() + ")");
  }
  if (!s) throw ApiError(409, "id", "sweep " + std::to_string(sweep_id) + " is not adaptive");
  const adaptive::LevelsSpec spec = levels_spec(s->plan);
  const adaptive::RunCost cost = cost_of(s->plan);
  PlanReport r;
  r.spec = *s->plan.adaptive;
  r.replicates = s->plan.replicates;
  r.budget_cpu_seconds = s->plan.budget_cpu_seconds;
  r.done = s->runs.done.size();
  r.pending = s->runs.pending.size();
  for (const auto& run : s->runs.done) r.cpu_seconds += cost(run.point, run.level);
  for (const auto& run : s->runs.pending) r.cpu_seconds += cost(run.point, run.level);
  r.cancelled = s->cancelled;
  r.resolved = s->runs.pending.empty() && adaptive::levels_resolved(spec, s->runs.done, cost);
  r.candidates = adaptive::ranked_level_actions(spec, s->runs.done, s->runs.pending, cost);
  const std::size_t room = spec.box.in_flight > r.pending ? spec.box.in_flight - r.pending : 0;
  r.levels = level_reports(*s, adaptive::next_level_actions(spec, s->runs.done, s->runs.pending, cost, room));
  r.columns = adaptive::column_resolution(spec, adaptive::node_labels(spec, s->runs.done));
  return r;
}

std::size_t AdaptiveSweeps::advance(Store& store, const PlannerLimits& limits,
                                    std::int64_t sweep_id, Millis now) {
  std::lock_guard lock(mutex_);
  std::size_t added = 0;
  try {
    plan_more(store, limits, sweep_id, now, added);
  } catch (const std::exception& e) {
    // The result or the sweep that called is stored; planning resumes with the next result,
    // the next lease expiry or the next start.
    spdlog::error("adaptive sweep {}: planning stopped: {}", sweep_id, e.what());
  }
  return added;
}

void AdaptiveSweeps::plan_more(Store& store, const PlannerLimits& limits, std::int64_t sweep_id,
                               Millis now, std::size_t& added) {
  // Each round adds at least one point the sweep did not hold, and the budget bounds them.
  while (true) {
    std::optional<SweepState> s;
    try {
      s = load(store, limits, sweep_id);
    } catch (const ApiError& e) {
      // Accepted once, refused now: the server's limits changed since (e.g. --max-sweep-points).
      spdlog::error("adaptive sweep {}: its request no longer plans ({}: {}); not advanced",
                    sweep_id, e.field, e.what());
      return;
    }
    if (!s || s->cancelled) return;
    const SweepPlan& plan = s->plan;
    const adaptive::LevelsSpec spec = levels_spec(plan);
    const adaptive::RunCost cost = cost_of(plan);
    const auto& done = s->runs.done;
    const auto& pending = s->runs.pending;
    const std::size_t room = spec.box.in_flight > pending.size() ? spec.box.in_flight - pending.size() : 0;
    const auto actions = adaptive::next_level_actions(spec, done, pending, cost, room);
    if (actions.empty()) {
      if (pending.empty()) {
        spdlog::info("adaptive sweep {} finished: {} runs of a budget of {}, boundaries {}",
                     sweep_id, done.size(), plan.adaptive->budget,
                     adaptive::levels_resolved(spec, done, cost) ? "resolved" : "not resolved");
      }
      return;
    }
    std::vector<NewJob> rows;
    for (const SceneParams& p : adaptive_scenes(plan, actions, limits)) {
      rows.push_back(job_row(p, store.config().engine_version));
    }
    const auto c = store.sweeps.add_jobs(sweep_id, rows, plan.priority, plan.max_attempts, now);
    if (!c) return;
    added += static_cast<std::size_t>(c->n_jobs);
    spdlog::info("adaptive sweep {}: {} points added ({} new, {} reused, {} shared, {} requeued), "
                 "{} of a budget of {}", sweep_id, c->n_jobs, c->n_new, c->n_reused, c->n_shared,
                 c->n_requeued, done.size() + pending.size() + rows.size(), plan.adaptive->budget);
    if (c->n_reused == 0) return;  // every new point waits for its run
  }
}

void AdaptiveSweeps::job_ended(Store& store, const PlannerLimits& limits, std::int64_t job_id,
                               Millis now) {
  advance_each(store, limits, store.reads.live_adaptive_sweeps_of_job(job_id), now);
}

std::size_t AdaptiveSweeps::advance_each(Store& store, const PlannerLimits& limits,
                                         const std::vector<std::int64_t>& sweep_ids, Millis now) {
  std::size_t added = 0;
  for (std::int64_t id : sweep_ids) added += advance(store, limits, id, now);
  return added;
}

void AdaptiveSweeps::advance_all(Store& store, const PlannerLimits& limits, Millis now) {
  for (std::int64_t id : store.reads.live_adaptive_sweeps()) advance(store, limits, id, now);
}

}  // namespace compaction::server
