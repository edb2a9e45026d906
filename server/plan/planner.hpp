// Sweep planning: turns a POST /api/v1/sweeps body into the list of scenes to compute.
//
//   {"name": "demo",
//    "points": [{"S": 0.05, "R": 0.001, "phi": 0.4}, ...]          explicit list, or a grid:
//    "S": {"min": 1e-3, "max": 1e-1, "n": 6, "scale": "log"},       range (log or linear)
//    "R": [1e-5, 1e-3],                                             explicit values
//    "phi": 0.4,                                                    one value
//    "numerics": {"preset": "fast", "cells_per_unit": 8, "eps_end": 0.05, ...},
//                 ("structure": "random", "seeds": [1, 2, 3] runs each point once per seed)
//    "replicates": {"n": 4, "perturbation": 0.01},                  or n runs of each point, the
//                                                                   particles perturbed, seeds 1..n
//    "priority": 0, "max_attempts": 3}
//
// or an adaptive sweep over one phi, which starts from a grid and grows where labels differ
// (adaptive_plan.hpp; adaptive_sweeps.hpp adds its points as results arrive):
//    "adaptive": {"S": {"min": 1e-3, "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1},
//                 "initial": {"S": 5, "R": 5}, "resolution_decades": 0.125, "budget": 200}
//
// The replicates of a point (numerics.seeds or replicates: the explicit seeds or their count) are
// runs of one scene up to its seed; the store groups them into the map's point (migration 0011,
// map_points.hpp). An adaptive sweep runs each of its points with every seed.
//
// Every scene is read with compaction::read_json (strict types) and validated once, per point
// (validate()'s ranges, with the point's S, R and phi). Errors
// name the field of the request ("points[2].phi", "S.min", "numerics.cfl") and are thrown as
// ApiError: 422 for invalid values, 413 for a sweep above the size limit.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"
#include "plan/adaptive_plan.hpp"
#include "plan/levels_plan.hpp"
#include "store/sweep_store.hpp"

namespace compaction::server {

// The rules of a sweep request beyond the scene's (compaction::limits), served by
// GET /api/v1/limits so the dashboard's form checks what the planner checks.
inline constexpr std::size_t kMaxNameBytes = 200;
inline constexpr int kPriorityMin = -1000, kPriorityMax = 1000, kDefaultPriority = 0;
inline constexpr int kDefaultMaxAttempts = 3;
inline constexpr std::size_t kMaxSeeds = 100;  // replicates.n, numerics.seeds: runs per point

struct PlannerLimits {
  std::size_t max_points = 2000;  // scenes per sweep
  int max_attempts = 10;          // upper bound of a sweep's max_attempts
  std::size_t max_bundle_bytes = std::size_t(256) << 20;  // the server's result upload limit
};

struct SweepPlan {
  std::string name;
  int priority = 0;       // higher runs first, in [-1000, 1000]
  int max_attempts = 3;   // runs of a job before it stays failed
  std::string preset;     // the resolution preset the numerics started from
  std::size_t replicates = 1;  // runs per point: its seeds (replicates.n or numerics.seeds)
  std::vector<SceneParams> scenes;  // distinct, in request order (an adaptive sweep's first grid)
  nlohmann::json request;           // the body as accepted
  std::optional<adaptive::AdaptiveSpec> adaptive;  // set for an adaptive sweep
  // An adaptive sweep's levels of numerics, coarse to fine (S, R and phi set per run; one level
  // without "levels"), its phi, the seeds of its replicates (replicate r runs with seeds[r];
  // empty: the scene's own seed) and its budget in CPU seconds (infinite without one).
  std::vector<SceneParams> levels;
  double adaptive_phi = 0;
  std::vector<std::uint64_t> seeds;
  double budget_cpu_seconds = std::numeric_limits<double>::infinity();
};

SweepPlan plan_sweep(const nlohmann::json& body, const PlannerLimits& limits = {});

// The rows the sweep store writes for a plan, each job's identity made with the engine version
// the new jobs are queued for.
NewSweep sweep_rows(const SweepPlan& plan, const std::string& engine_version);
NewJob job_row(const SceneParams& p, const std::string& engine_version);

// An adaptive sweep's runs: the scenes of the planner's actions (each its level's numerics at its
// point, with the seed of its replicate), validated; the scene of a level at a point without
// validation, and the cost model's CPU seconds of its run; the planner's spec.
std::vector<SceneParams> adaptive_scenes(const SweepPlan& plan,
                                         const std::vector<adaptive::LevelAction>& actions,
                                         const PlannerLimits& limits = {});
SceneParams level_scene(const SweepPlan& plan, int level, adaptive::Point at);
double run_cpu_seconds(const SweepPlan& plan, adaptive::Point at, int level);
adaptive::LevelsSpec levels_spec(const SweepPlan& plan);

// The solid fractions a stored request covers, in its order (its points' phi, or its phi axis,
// else the scene's default): what the dashboard lists a sweep under. A request this server
// cannot read (an import of another version) covers none.
std::vector<double> request_phis(const nlohmann::json& request);
inline constexpr std::size_t kMaxRequestPhis = 1000;

// Values of one grid axis: a number, an array of numbers, or {"min","max","n","scale"}.
// Throws ApiError naming `field` (e.g. "S.n").
std::vector<double> expand_axis(const nlohmann::json& axis, const std::string& field,
                                std::size_t max_points);

// Canonical form of a scene (compaction::to_json with threads = 1, which does not change the
// result) and the identity of its computation: engine version + canonical JSON.
std::string canonical_scene(const SceneParams& p);
std::string job_identity(const SceneParams& p, const std::string& engine_version);

}  // namespace compaction::server
