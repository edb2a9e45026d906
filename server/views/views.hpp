// The REST API's JSON documents, built from the store's records (store_reads.hpp): a change
// of a field the API answers touches this file, never SQL.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "plan/adaptive_sweeps.hpp"
#include "plan/phase_regions.hpp"
#include "store/store_reads.hpp"
#include "store/sweep_store.hpp"

namespace compaction::server::views {

nlohmann::json sweep(const SweepRecord& s);
nlohmann::json sweeps(const Page<SweepRecord>& page, int limit, int offset);
nlohmann::json created_sweep(const SweepRecord& s, const CreatedSweep& c, const std::string& preset);
nlohmann::json cancelled_sweep(std::int64_t id, std::int64_t cancelled_jobs);
// An adaptive sweep's plan: its state, runs against the budget and the equivalent full grid,
// and the first `limit` of the candidates the planner ranks now.
nlohmann::json sweep_plan(std::int64_t id, const PlanReport& r, std::size_t limit);
nlohmann::json job(const JobRecord& j);
nlohmann::json job_detail(const JobDetail& d);
nlohmann::json sweep_jobs(const std::vector<JobRecord>& rows);
// The phase map as JSON text, written directly: 10 000 points as json objects took most of the
// answer's time (an object per point, a map node per field).
std::string phase_map(double phi, const std::vector<PhaseMapPoint>& points);
// The points of these runs (map_points.hpp), as the phase map's "summaries" array: JSON text.
std::string point_summaries(const std::vector<PhaseMapPoint>& runs);
// What the model predicts at phi (compaction/params.hpp): the struts' fraction of the unit cell
// and aspect ratio, the buckling onset R_crit, the non-reflecting band's speed; null outside (0, 1).
nlohmann::json model(double phi);
nlohmann::json artifacts(std::int64_t job_id, const std::vector<ArtifactInfo>& list);
// What a sweep would cost (POST /sweeps/estimate): its jobs, CPU time from the cost model and
// the time to finish on the workers connected (null without one).
struct SweepEstimate {
  std::size_t jobs = 0, max_jobs = 0;     // max_jobs: an adaptive sweep's budget, else jobs
  double cpu_seconds = 0, max_cpu_seconds = 0;
  std::size_t workers = 0;                // seen within the lease time
  double lease_seconds = 0;
};
nlohmann::json sweep_estimate(const SweepEstimate& e);
// The predicted regions at phi: the box, one string of class letters per row of R ('.': no
// class) and the uncertainties rounded to 3 decimals, with the filters and the rule's constants.
nlohmann::json phase_regions(double phi, std::optional<std::int64_t> sweep,
                             std::optional<std::int64_t> cells_per_unit,
                             const std::optional<regions::Regions>& r);

}  // namespace compaction::server::views
