// A store with a run of each kind the run table tells apart (store/run_table.hpp), written
// through the stores as the server writes them: four sweeps (one of the fast preset, one of
// three replicates per point at the default preset, one of a grid of its own, one reusing a
// run of the first), results of every class with their confidences, reflections and band
// speeds (one unstable), a failed, a running and queued jobs, two human labels (one changed),
// and two runs imported from another database's export.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "compaction/result.hpp"
#include "exchange/export_format.hpp"
#include "exchange/result_intake.hpp"
#include "plan/planner.hpp"
#include "store/store.hpp"
#include "temp_dir.hpp"

namespace compaction::server::run_table_fill {

using nlohmann::json;

inline constexpr Millis t0 = 1'700'000'000'000;

inline std::int64_t create(Store& s, const json& body) {
  return s.sweeps.create(sweep_rows(plan_sweep(body), s.config().engine_version), t0).id;
}

// Classifier features that tell the runs apart (the run table's feature columns, migration
// 0015): numbers from the classification's, an integer and a NaN the summary writes as null
// (NULL in the table).
inline json features_of(double confidence, int n_reflections) {
  return {{"deflection_before_yield", confidence / 10.0},
          {"coherence", 1.0 - confidence},
          {"n_fronts", n_reflections + 1},
          {"stress_ratio", n_reflections == 0 ? json(nullptr) : json(0.5 * n_reflections)},
          {"peak_jump", n_reflections},
          {"primary_origin", "top"}};
}

// Leases the next job and uploads the engine's summary of its scene with this classification,
// through the checks of a worker's upload. Returns the job's id (0: nothing queued).
inline std::int64_t complete_next(Store& s, const std::string& cls, double confidence,
                                  int n_reflections, double band_speed_ratio,
                                  const std::string& status = "ok") {
  const auto l = s.queue.lease("w1", s.config().engine_version, t0 + 10);
  if (!l) return 0;
  compaction::SceneParams p;
  EXPECT_TRUE(compaction::from_json(json::parse(l->scene), p).empty());
  compaction::RunResult run;
  run.eps_reached = p.eps_end;
  json summary = compaction::summary_json(p, run);
  summary["status"] = status;
  if (status != "ok") summary["reason"] = "energy blew up";
  summary["classification"] = {{"class", cls},
                               {"confidence", confidence},
                               {"runner_up", cls == "a" ? "b" : "a"},
                               {"n_reflections", n_reflections},
                               {"band_speed_ratio", band_speed_ratio},
                               {"features", features_of(confidence, n_reflections)}};
  const ResultRecord r = intake_result(summary.dump(), l->scene, s.config().engine_version,
                                       {{"frames.csv", "eps,sigma_top\n0.01,1\n"}});
  EXPECT_EQ(s.queue.complete(l->job_id, l->token, r, t0 + 20), LeaseCheck::ok);
  return l->job_id;
}

inline json numerics(const json& extra) {
  json n = {{"eps_end", 0.05}};
  n.update(extra);
  return n;
}

struct Filled {
  std::int64_t fast = 0, replicas = 0, own_grid = 0, overlap = 0, imported = 0;
  std::string source;  // the id of the database the imported runs come from
};

// The runs of the header's comment, in `s`; the imported ones computed in a second store in
// `dir`.
inline Filled fill(Store& s, const TempDir& dir) {
  Filled f;
  f.fast = create(s, {{"name", "fig two"}, {"phi", 0.4}, {"S", {1e-3, 1e-2, 0.1}}, {"R", {1e-4, 1e-2}},
                      {"numerics", numerics({{"preset", "fast"}})}});                       // jobs 1-6
  f.replicas = create(s, {{"name", "replicas"}, {"points", {{{"S", 0.02}, {"R", 1e-3}, {"phi", 0.5}},
                                                           {{"S", 0.2}, {"R", 1e-3}, {"phi", 0.5}}}},
                          {"replicates", {{"n", 3}, {"perturbation", 0.01}}},
                          {"numerics", numerics({{"preset", "default"}})}});                  // 7-12
  f.own_grid = create(s, {{"name", "a grid of its own"}, {"phi", 0.3}, {"S", 0.05}, {"R", {1e-3, 1e-2}},
                          {"numerics", numerics({{"cells_per_unit", 10}})}});                 // 13-14
  f.overlap = create(s, {{"name", "trusted map"}, {"phi", 0.4}, {"S", 1e-3}, {"R", 1e-4},
                         {"numerics", numerics({{"preset", "fast"}})}});                      // job 1
  // Ten results of every class, one unstable; then one run failed, one running, three queued.
  const char* classes = "abcdefabcd";
  for (int i = 0; i < 10; ++i) {
    complete_next(s, std::string(1, classes[i]), 0.1 + 0.08 * i, i % 4, 1.0 + 0.25 * i,
                  i == 4 ? "unstable" : "ok");
  }
  if (const auto l = s.queue.lease("w1", s.config().engine_version, t0 + 30)) {
    s.queue.fail(l->job_id, l->token, "the runner crashed", false, t0 + 31);
  }
  s.queue.lease("w2", s.config().engine_version, t0 + 40);
  // A person's labels: job 2's set and changed, job 3's set.
  s.labels.set(2, {"c", "first look", "ben", t0 + 50, "open", std::nullopt});
  s.labels.set(2, {"d", "buckles at the plate", "ana", t0 + 51, "open", std::nullopt});
  s.labels.set(3, {"a", "one reflection only", "ben", t0 + 52, "open", std::nullopt});

  // Two runs of another database, at phi 0.45, imported.
  Store other(dir.file("other.db"), s.config());
  const std::int64_t part = create(other, {{"name", "part B"}, {"phi", 0.45}, {"S", {0.03, 0.3}}, {"R", 1e-3},
                                           {"numerics", numerics({{"preset", "fast"}})}});
  complete_next(other, "e", 0.95, 2, 3.0);
  complete_next(other, "f", 0.5, 0, 4.0);
  const ImportOutcome o =
      s.imports.merge(read_export(*export_sweep(other, part, "127.0.0.1:8080", t0 + 60)), t0 + 70);
  f.imported = o.sweep_id;
  f.source = other.imports.database_id();
  return f;
}

}  // namespace compaction::server::run_table_fill
