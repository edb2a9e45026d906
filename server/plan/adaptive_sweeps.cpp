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

// The sweep's points: finished (every replicate ended; the point's label from its replicates,
// point_tally.hpp) and waiting (a replicate still queued or running). Runs counted too.
struct SweepPoints {
  std::vector<adaptive::Labelled> done;
  std::vector<adaptive::Point> pending;
  std::size_t runs_done = 0, runs_pending = 0;
};

SweepPoints split_points(const std::vector<JobRecord>& jobs) {
  std::map<std::pair<double, double>, std::vector<const JobRecord*>> points;  // by (S, R)
  for (const JobRecord& j : jobs) points[{j.S, j.R}].push_back(&j);
  SweepPoints out;
  for (const auto& [at, runs] : points) {
    const adaptive::Point pt{at.first, at.second};
    std::vector<adaptive::Labelled> finished;
    for (const JobRecord* j : runs) {
      if (j->state == "queued" || j->state == "running") continue;
      if (j->state != "succeeded") {
        finished.push_back({pt, std::nullopt, 0.0, std::nullopt});  // failed, cancelled: unknown
        continue;
      }
      // The classifier's label is none for an unstable or unclassified run.
      const std::optional<std::string> human =
          j->human_label ? std::optional<std::string>(j->human_label->label) : std::nullopt;
      const auto& r = j->result;
      finished.push_back(counted_label(pt, human, r ? r->cls : std::nullopt,
                                       r ? r->confidence : std::nullopt, r ? r->runner_up : std::nullopt));
    }
    out.runs_done += finished.size();
    out.runs_pending += runs.size() - finished.size();
    if (finished.size() < runs.size()) {
      out.pending.push_back(pt);
    } else {
      out.done.push_back(tally(pt, finished, runs.size()).as_run);
    }
  }
  return out;
}

// The spec as the planner counts it, in points: the request's budget and in_flight count runs,
// and each point takes its replicates.
adaptive::AdaptiveSpec point_spec(const SweepPlan& plan) {
  adaptive::AdaptiveSpec s = *plan.adaptive;
  s.budget /= plan.replicates;
  s.in_flight = std::max<std::size_t>(1, s.in_flight / plan.replicates);
  return s;
}

// An adaptive sweep as the planner reads it: its plan from the stored request and its points.
struct SweepState {
  SweepPlan plan;
  bool cancelled = false;
  SweepPoints points;
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
  s.points = split_points(*jobs);
  return s;
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
  const adaptive::AdaptiveSpec spec = point_spec(s->plan);
  PlanReport r;
  r.spec = *s->plan.adaptive;
  r.replicates = s->plan.replicates;
  r.done = s->points.runs_done;
  r.pending = s->points.runs_pending;
  r.points_done = s->points.done.size();
  r.points_pending = s->points.pending.size();
  r.cancelled = s->cancelled;
  r.resolved = adaptive::resolved(spec, s->points.done);
  r.candidates = adaptive::ranked_candidates(spec, s->points.done, s->points.pending);
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
    const adaptive::AdaptiveSpec spec = point_spec(plan);
    const auto& done = s->points.done;
    const auto& pending = s->points.pending;
    const std::size_t room = spec.in_flight > pending.size() ? spec.in_flight - pending.size() : 0;
    const auto points = adaptive::next_points(spec, done, pending, room);
    if (points.empty()) {
      if (pending.empty()) {
        spdlog::info("adaptive sweep {} finished: {} runs of a budget of {}, boundaries {}",
                     sweep_id, s->points.runs_done, plan.adaptive->budget,
                     adaptive::resolved(spec, done) ? "resolved" : "not resolved");
      }
      return;
    }
    std::vector<NewJob> rows;
    for (const SceneParams& p : adaptive_scenes(plan, points, limits)) {
      rows.push_back(job_row(p, store.config().engine_version));
    }
    const auto c = store.sweeps.add_jobs(sweep_id, rows, plan.priority, plan.max_attempts, now);
    if (!c) return;
    added += static_cast<std::size_t>(c->n_jobs);
    spdlog::info("adaptive sweep {}: {} points added ({} new, {} reused, {} shared, {} requeued), "
                 "{} of a budget of {}", sweep_id, c->n_jobs, c->n_new, c->n_reused, c->n_shared,
                 c->n_requeued, s->points.runs_done + s->points.runs_pending + rows.size(),
                 plan.adaptive->budget);
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
