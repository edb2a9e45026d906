#include "plan/planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>

#include "compaction/bundle.hpp"
#include "compaction/number_text.hpp"
#include "compaction/params_json.hpp"
#include "compaction/presets.hpp"
#include "input/api_error.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"
#include "plan/cost_model.hpp"
#include "plan/round_significant.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// Numerics keys a sweep may set (the rest of SceneParams is fixed by the model or per point).
const std::set<std::string> numerics_keys = {
    "preset", "cells_per_strut", "cells_per_unit", "particles_per_cell", "cfl", "transfer",
    "movie_d_eps",
    "flip_ratio", "eps_end", "d_eps", "snapshot_eps", "contact", "pore_contact", "perturbation", "seed",
    "structure", "seeds", "geometry"};

// Numerics keys a level of an adaptive sweep may set: what sets the resolution and the transfer.
const std::set<std::string> level_keys = {"preset", "cells_per_strut", "cells_per_unit",
                                          "particles_per_cell", "cfl", "transfer", "flip_ratio",
                                          "pore_contact"};

const std::set<std::string> request_keys = {"name",     "points",       "S",       "R",
                                            "phi",      "numerics",     "priority", "max_attempts",
                                            "adaptive", "replicates"};

[[noreturn]] void invalid(const std::string& field, const std::string& message,
                          int status = 422) {
  throw ApiError(status, field, message);
}

bool finite_number(const json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

using text::num;

int integer_in(const json& body, const char* key, int fallback, int lo, int hi) {
  if (!body.contains(key)) return fallback;
  const json& v = body[key];
  if (!v.is_number_integer()) invalid(key, std::string("must be an integer, got ") + describe(v));
  const auto i = as_int64(v);
  if (!i || *i < lo || *i > hi) {
    invalid(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                     describe(v));
  }
  return static_cast<int>(*i);
}

// numerics.seeds: 1 to kMaxSeeds distinct non-negative integers.
std::vector<std::uint64_t> seed_list(const json& v) {
  if (!v.is_array()) invalid("numerics.seeds", "must be an array of seeds, got " + describe(v));
  if (v.empty() || v.size() > kMaxSeeds) {
    invalid("numerics.seeds", "must hold 1 to " + std::to_string(kMaxSeeds) + " seeds, got " +
                                  std::to_string(v.size()));
  }
  std::vector<std::uint64_t> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string field = "numerics.seeds[" + std::to_string(i) + "]";
    if (!v[i].is_number_unsigned()) {  // as compaction::from_json reads seed
      invalid(field, "must be a non-negative integer, got " + describe(v[i]));
    }
    const auto seed = v[i].get<std::uint64_t>();
    if (std::find(out.begin(), out.end(), seed) != out.end()) {
      invalid(field, "repeats seed " + std::to_string(seed));
    }
    out.push_back(seed);
  }
  return out;
}

// The field a request names its replicates in: replicates, else numerics.seeds.
std::string replicates_field(const json& request) {
  return request.contains("replicates") ? "replicates" : "numerics.seeds";
}

// replicates: {"n": 1 to kMaxSeeds, "perturbation": in the engine's range}, run with the seeds
// 1..n; moves the perturbation into the numerics. numerics.seed, numerics.seeds and a second
// perturbation beside it are refused: each replicate's seed and the perturbation have one home.
std::vector<std::uint64_t> read_replicates(const json& r, json& numerics) {
  if (!r.is_object()) {
    invalid("replicates", "must be an object {\"n\": runs per point, \"perturbation\": "
                          "fraction of the particle spacing}, got " + describe(r));
  }
  for (const auto& [key, value] : r.items()) {
    if (key != "n" && key != "perturbation") {
      invalid("replicates." + key, "unknown key (expected n, perturbation)");
    }
  }
  for (const char* key : {"seed", "seeds"}) {
    if (numerics.contains(key)) {
      invalid("numerics." + std::string(key),
              "give replicates (seeds 1..n) or numerics.seed/seeds, not both");
    }
  }
  if (!r.contains("n")) invalid("replicates.n", "is required");
  if (!r["n"].is_number_integer()) invalid("replicates.n", "must be an integer, got " + describe(r["n"]));
  const auto n = as_int64(r["n"]);
  if (!n || *n < 1 || static_cast<std::size_t>(*n) > kMaxSeeds) {
    invalid("replicates.n", "must be in [1, " + std::to_string(kMaxSeeds) + "], got " + describe(r["n"]));
  }
  if (r.contains("perturbation")) {
    if (numerics.contains("perturbation")) {
      invalid("replicates.perturbation", "is given in numerics.perturbation too: give it once");
    }
    const json& v = r["perturbation"];
    if (!finite_number(v) || !limits::perturbation.contains(v.get<double>())) {
      invalid("replicates.perturbation", "must be a number in " + to_string(limits::perturbation) +
                                             " (a fraction of the particle spacing), got " + describe(v));
    }
    numerics["perturbation"] = v;
  }
  std::vector<std::uint64_t> seeds;
  for (long long i = 1; i <= *n; ++i) seeds.push_back(static_cast<std::uint64_t>(i));
  return seeds;
}

// A request's numerics as one JSON object of scene keys: the preset's values, then the explicit
// keys over them (threads 1); `seeds` the seeds each point runs with, one run per seed
// (replicates, or numerics.seeds; empty without them: each point runs once with the scene's
// seed); `explicit_keys` the request's own numerics (without preset and seeds).
json merged_numerics(const json& body, std::string& preset_name, std::vector<std::uint64_t>& seeds,
                     json& explicit_keys) {
  json numerics = json::object();
  if (body.contains("numerics")) {
    numerics = body["numerics"];
    if (!numerics.is_object()) invalid("numerics", "must be an object, got " + describe(numerics));
  }
  for (const auto& [key, value] : numerics.items()) {
    if (!numerics_keys.count(key)) invalid("numerics." + key, "unknown numerics key");
  }
  seeds.clear();
  if (body.contains("replicates")) {
    seeds = read_replicates(body["replicates"], numerics);
  } else if (numerics.contains("seeds")) {
    if (numerics.contains("seed")) invalid("numerics.seeds", "give seed or seeds, not both");
    seeds = seed_list(numerics["seeds"]);
    numerics.erase("seeds");
  }
  preset_name = std::string(compaction::kDefaultPreset);
  if (numerics.contains("preset")) {
    const json& p = numerics["preset"];
    if (!p.is_string() || !compaction::find_preset(p.get<std::string>())) {
      invalid("numerics.preset", "must be one of " + compaction::preset_names() + ", got " + describe(p));
    }
    preset_name = p.get<std::string>();
    numerics.erase("preset");
  }
  explicit_keys = numerics;
  json merged = compaction::preset_json(*compaction::find_preset(preset_name));
  for (const auto& [key, value] : numerics.items()) merged[key] = value;
  merged["threads"] = 1;
  return merged;
}

// A scene from merged numerics: their types only, here; the ranges (some depend on phi) are
// validated once, per point, with the point's S, R and phi. Errors are named `prefix` + key.
SceneParams read_scene(const json& merged, const std::string& prefix) {
  SceneParams scene;
  if (std::vector<FieldError> errors = read_json(merged, scene); !errors.empty()) {
    std::vector<FieldError> named;
    for (auto& e : errors) named.push_back({prefix + e.field, e.message});
    throw ApiError(422, std::move(named));
  }
  return scene;
}

// The scene every point starts from: preset, then the explicit numerics over it; `seeds` as
// merged_numerics says.
SceneParams base_scene(const json& body, std::string& preset_name,
                       std::vector<std::uint64_t>& seeds) {
  json explicit_keys;
  const SceneParams scene = read_scene(merged_numerics(body, preset_name, seeds, explicit_keys), "numerics.");
  if (seeds.size() > 1 && scene.structure == Structure::regular && scene.perturbation == 0.0) {
    if (body.contains("replicates")) {
      invalid("replicates.perturbation",
              "is required: replicates of a regular structure without perturbation are one run "
              "repeated (or set numerics.structure to \"random\")");
    }
    invalid("numerics.seeds",
            "the seed changes nothing in a regular structure without perturbation: set "
            "numerics.structure to \"random\" (or a perturbation)");
  }
  return scene;
}

// Applies S, R, phi to the base scene and validates the whole, once; errors are prefixed by
// `where` for S, R and phi ("points[3].phi", or the axis name) and by "numerics." for the rest.
SceneParams make_scene(const SceneParams& base, double S, double R, double phi,
                       const std::string& where, const PlannerLimits& limits) {
  SceneParams p = base;
  p.S = S, p.R = R, p.phi = phi;
  if (phi == kSolidColumnPhi) {
    invalid(where + "phi", "must be in [" + num(kPhiMin) + ", " + num(kPhiMax) +
                               "] (the solid column, phi = 1, is for the engine's tests)");
  }
  std::vector<FieldError> errors = validate(p);
  if (!errors.empty()) {
    std::vector<FieldError> named;
    for (auto& e : errors) {
      const bool axis = e.field == "S" || e.field == "R" || e.field == "phi";
      named.push_back({axis ? where + e.field : "numerics." + e.field, e.message});
    }
    throw ApiError(422, std::move(named));
  }
  // A job names the contact it runs with (its identity and its page): "auto" resolved here.
  p.pore_contact = resolved_pore_contact(p);
  const std::size_t bundle = bundle_size_bound(p);
  if (bundle > limits.max_bundle_bytes) {
    // named after what takes most of it: the movie or the snapshots
    const bool movie = 2 * movie_size_bound(p) > bundle;
    invalid(movie ? "numerics.movie_d_eps" : "numerics.snapshot_eps",
            "the result at S = " + num(S) + ", R = " + num(R) + ", phi = " + num(phi) +
                " may take up to " + std::to_string(bundle >> 20) + " MiB, above the server's upload limit of " +
                std::to_string(limits.max_bundle_bytes >> 20) + " MiB: " +
                (movie ? "ask for a longer movie_d_eps (or 0: no movie)" : "ask for fewer snapshots"));
  }
  return p;
}

double point_value(const json& point, const char* key, const std::string& where) {
  if (!point.contains(key)) invalid(where + key, "is required");
  const json& v = point[key];
  if (!finite_number(v)) invalid(where + key, "must be a finite number, got " + describe(v));
  return v.get<double>();
}

}  // namespace

std::vector<double> request_phis(const json& request) {
  try {
    std::vector<double> out;
    if (request.contains("points") && request["points"].is_array()) {
      for (const json& p : request["points"]) {
        if (p.is_object() && p.contains("phi") && p["phi"].is_number()) out.push_back(p["phi"].get<double>());
      }
      return out;
    }
    return request.contains("phi") ? expand_axis(request["phi"], "phi", kMaxRequestPhis)
                                   : std::vector<double>{SceneParams{}.phi};
  } catch (const ApiError&) {
    return {};
  }
}

std::vector<double> expand_axis(const json& axis, const std::string& field,
                                std::size_t max_points) {
  if (axis.is_number()) {
    if (!finite_number(axis)) invalid(field, "must be a finite number");
    return {axis.get<double>()};
  }
  if (axis.is_array()) {
    if (axis.empty()) invalid(field, "must not be empty");
    if (axis.size() > max_points) {
      invalid(field, std::to_string(axis.size()) + " values exceed the sweep limit of " +
                         std::to_string(max_points) + " points", 413);
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < axis.size(); ++i) {
      if (!finite_number(axis[i])) {
        invalid(field + "[" + std::to_string(i) + "]",
                "must be a finite number, got " + describe(axis[i]));
      }
      out.push_back(axis[i].get<double>());
    }
    return out;
  }
  if (!axis.is_object()) {
    invalid(field, "must be a number, an array of numbers or {min, max, n, scale}, got " +
                       describe(axis));
  }
  for (const auto& [key, value] : axis.items()) {
    if (key != "min" && key != "max" && key != "n" && key != "scale") {
      invalid(field + "." + key, "unknown key (expected min, max, n, scale)");
    }
  }
  for (const char* key : {"min", "max"}) {
    if (!axis.contains(key)) invalid(field + "." + key, "is required");
    if (!finite_number(axis[key])) {
      invalid(field + "." + key, "must be a finite number, got " + describe(axis[key]));
    }
  }
  if (!axis.contains("n")) invalid(field + ".n", "is required");
  if (!axis["n"].is_number_integer()) {
    invalid(field + ".n", "must be an integer, got " + describe(axis["n"]));
  }
  const auto given = as_int64(axis["n"]);
  if (!given || *given < 1) invalid(field + ".n", "must be at least 1, got " + describe(axis["n"]));
  const long long n = *given;
  if (static_cast<unsigned long long>(n) > max_points) {
    invalid(field + ".n", std::to_string(n) + " values exceed the sweep limit of " +
                              std::to_string(max_points) + " points", 413);
  }
  std::string scale = "linear";
  if (axis.contains("scale")) {
    if (!axis["scale"].is_string() ||
        (axis["scale"] != "log" && axis["scale"] != "linear")) {
      invalid(field + ".scale", "must be \"log\" or \"linear\", got " + describe(axis["scale"]));
    }
    scale = axis["scale"].get<std::string>();
  }
  const double lo = axis["min"].get<double>(), hi = axis["max"].get<double>();
  if (lo > hi) invalid(field + ".max", "must be >= min (" + num(lo) + "), got " + num(hi));
  if (scale == "log" && lo <= 0.0) {
    invalid(field + ".min", "must be > 0 on a log scale, got " + num(lo));
  }
  std::vector<double> out;
  for (long long i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    const double v = scale == "log" ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
    out.push_back(round_significant(v));
  }
  out.front() = lo;  // the ends exactly as written
  out.back() = n == 1 ? lo : hi;
  return out;
}

std::string canonical_scene(const SceneParams& p) {
  SceneParams c = p;
  c.threads = 1;
  return compaction::to_json(c).dump();
}

std::string job_identity(const SceneParams& p, const std::string& engine_version) {
  return engine_version + "|" + canonical_scene(p);
}

NewJob job_row(const SceneParams& p, const std::string& engine_version) {
  return {job_identity(p, engine_version), canonical_scene(p), p.S, p.R, p.phi, p.eps_final(),
          p.grid_cells_per_unit(), to_string(p.structure)};
}

NewSweep sweep_rows(const SweepPlan& plan, const std::string& engine_version) {
  NewSweep out{plan.name, plan.request.dump(), plan.priority, plan.max_attempts, {}};
  for (const SceneParams& p : plan.scenes) out.jobs.push_back(job_row(p, engine_version));
  return out;
}

SceneParams level_scene(const SweepPlan& plan, int level, adaptive::Point at) {
  SceneParams p = plan.levels.at(static_cast<std::size_t>(level));
  p.S = at.S, p.R = at.R, p.phi = plan.adaptive_phi;
  p.pore_contact = resolved_pore_contact(p);
  return p;
}

double run_cpu_seconds(const SweepPlan& plan, adaptive::Point at, int level) {
  return cost::cpu_seconds(level_scene(plan, level, at));
}

adaptive::LevelsSpec levels_spec(const SweepPlan& plan) {
  adaptive::LevelsSpec spec;
  spec.box = *plan.adaptive;
  spec.levels = static_cast<int>(plan.levels.size());
  spec.replicates = plan.replicates;
  spec.budget_cpu_seconds = plan.budget_cpu_seconds;
  return spec;
}

std::vector<SceneParams> adaptive_scenes(const SweepPlan& plan,
                                         const std::vector<adaptive::LevelAction>& actions,
                                         const PlannerLimits& limits) {
  std::vector<SceneParams> out;
  for (const adaptive::LevelAction& a : actions) {
    SceneParams p = make_scene(plan.levels.at(static_cast<std::size_t>(a.level)), a.point.S,
                               a.point.R, plan.adaptive_phi, "", limits);
    if (!plan.seeds.empty()) p.seed = plan.seeds.at(a.replicate);
    out.push_back(std::move(p));
  }
  return out;
}

namespace {

// name, priority and max_attempts.
void read_header(const json& body, const PlannerLimits& limits, SweepPlan& plan) {
  if (!body.contains("name")) invalid("name", "is required");
  if (!body["name"].is_string()) invalid("name", "must be a string, got " + describe(body["name"]));
  plan.name = body["name"].get<std::string>();
  if (plan.name.empty() || plan.name.size() > kMaxNameBytes) {
    invalid("name", "must be 1 to " + std::to_string(kMaxNameBytes) + " bytes");
  }
  if (has_control_characters(plan.name)) invalid("name", "must not hold control characters");
  plan.priority = integer_in(body, "priority", kDefaultPriority, kPriorityMin, kPriorityMax);
  plan.max_attempts = integer_in(body, "max_attempts", kDefaultMaxAttempts, 1, limits.max_attempts);
}

// The sweep's scenes: each point once per replicate seed, a scene already listed not again.
struct SceneList {
  SweepPlan& plan;
  const std::vector<std::uint64_t>& seeds;  // empty: each point once, with the scene's seed
  const PlannerLimits& limits;
  std::set<std::string> seen;

  std::size_t per_point() const { return std::max<std::size_t>(1, seeds.size()); }

  // Refuses a sweep whose points x replicates exceed the sweep limit.
  void check_count(std::size_t points) const {
    if (per_point() > 1 && static_cast<double>(points) * per_point() > limits.max_points) {
      invalid(replicates_field(plan.request), std::to_string(points) + " points x " +
                                                   std::to_string(per_point()) +
                                                   " replicates exceed the sweep limit of " +
                                                   std::to_string(limits.max_points) + " runs",
              413);
    }
  }

  void add(SceneParams p) {
    if (seeds.empty()) return add_one(std::move(p));
    for (std::uint64_t seed : seeds) {
      p.seed = seed;
      add_one(p);
    }
  }

  void add_one(SceneParams p) {
    if (seen.insert(canonical_scene(p)).second) plan.scenes.push_back(std::move(p));
  }
};

// An error of a level's scene named after the level: "numerics.cells_per_strut" from its
// validation becomes "adaptive.levels[1].cells_per_strut".
[[noreturn]] void rethrow_for_level(const ApiError& e, const std::string& field) {
  std::vector<FieldError> named;
  const auto rename = [&](const std::string& f) {
    return f.rfind("numerics.", 0) == 0 ? field + "." + f.substr(9) : field + "." + f;
  };
  if (e.details.empty()) throw ApiError(e.status, rename(e.field), e.what());
  for (const FieldError& d : e.details) named.push_back({rename(d.field), d.message});
  throw ApiError(e.status, std::move(named));
}

// The scenes of an adaptive sweep's levels, coarse to fine (the sweep's own numerics alone
// without "levels"): each level's keys over the sweep's numerics, or over its own preset with
// the sweep's explicit keys; each validated at `probe` and strictly finer than the one before.
std::vector<SceneParams> level_scenes(const json& body, const SceneParams& base, double phi,
                                      adaptive::Point probe, const PlannerLimits& limits) {
  const json& spec = body["adaptive"];
  if (!spec.contains("levels")) return {base};
  const json& levels = spec["levels"];
  if (!levels.is_array() || levels.empty() || levels.size() > adaptive::kMaxLevels) {
    invalid("adaptive.levels", "must be an array of 1 to " + std::to_string(adaptive::kMaxLevels) +
                                   " levels of numerics, coarse to fine, got " + describe(levels));
  }
  std::string preset;
  std::vector<std::uint64_t> seeds;
  json explicit_keys;
  const json merged = merged_numerics(body, preset, seeds, explicit_keys);
  std::vector<SceneParams> out;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const std::string field = "adaptive.levels[" + std::to_string(i) + "]";
    const json& level = levels[i];
    if (!level.is_object()) invalid(field, "must be an object of numerics, got " + describe(level));
    for (const auto& [key, value] : level.items()) {
      if (!level_keys.count(key)) {
        invalid(field + "." + key, "unknown level key (a level sets the resolution: preset, "
                                   "cells_per_strut, cells_per_unit, particles_per_cell, cfl, "
                                   "transfer, flip_ratio, pore_contact)");
      }
    }
    json m = merged;
    if (level.contains("preset")) {
      const json& p = level["preset"];
      if (!p.is_string() || !compaction::find_preset(p.get<std::string>())) {
        invalid(field + ".preset", "must be one of " + compaction::preset_names() + ", got " + describe(p));
      }
      m = compaction::preset_json(*compaction::find_preset(p.get<std::string>()));
      for (const auto& [key, value] : explicit_keys.items()) m[key] = value;
      m["threads"] = 1;
    }
    for (const auto& [key, value] : level.items()) {
      if (key != "preset") m[key] = value;
    }
    SceneParams scene = read_scene(m, field + ".");
    if (!seeds.empty()) scene.seed = seeds.front();
    try {
      make_scene(scene, probe.S, probe.R, phi, "", limits);
    } catch (const ApiError& e) {
      rethrow_for_level(e, field);
    }
    SceneParams at_phi = scene;
    at_phi.phi = phi;
    if (!out.empty()) {
      SceneParams coarser = out.back();
      coarser.phi = phi;
      if (at_phi.grid_cells_per_unit() <= coarser.grid_cells_per_unit()) {
        invalid(field, "must be finer than the level before it (" +
                           std::to_string(coarser.grid_cells_per_unit()) +
                           " grid cells per unit cell), got " +
                           std::to_string(at_phi.grid_cells_per_unit()));
      }
    }
    out.push_back(std::move(scene));
  }
  return out;
}

// adaptive.budget_cpu_hours: a positive number of CPU-hours, at least what the initial grid costs
// at the coarsest level (by the cost model); none: no limit but the budget in runs.
double cpu_budget(const json& spec, double initial_cpu_seconds) {
  if (!spec.contains("budget_cpu_hours")) return std::numeric_limits<double>::infinity();
  const json& v = spec["budget_cpu_hours"];
  if (!finite_number(v) || !(v.get<double>() > 0)) {
    invalid("adaptive.budget_cpu_hours", "must be a positive number of CPU-hours, got " + describe(v));
  }
  const double seconds = v.get<double>() * 3600.0;
  if (seconds < initial_cpu_seconds) {
    invalid("adaptive.budget_cpu_hours",
            "must cover the initial grid at the first level, " + num(initial_cpu_seconds / 3600.0) +
                " CPU-hours by the cost model, got " + num(v.get<double>()));
  }
  return seconds;
}

// A box of S and R at one phi, from which the sweep grows (adaptive_plan.hpp, levels_plan.hpp):
// the initial grid now, one run a point at the coarsest level; the rest as results arrive
// (adaptive_sweeps.hpp).
void plan_adaptive(const json& body, const SceneParams& base, SceneList& scenes) {
  SweepPlan& plan = scenes.plan;
  for (const char* key : {"points", "S", "R"}) {
    if (body.contains(key)) {
      invalid(key, "an adaptive sweep takes its S and R box inside \"adaptive\", not beside it");
    }
  }
  if (!body.contains("phi")) invalid("phi", "is required: an adaptive sweep maps one phi");
  const auto phi = expand_axis(body["phi"], "phi", scenes.limits.max_points);
  if (phi.size() != 1) {
    invalid("phi", "an adaptive sweep maps one phi, got " + std::to_string(phi.size()) + " values");
  }
  plan.adaptive = adaptive::parse_spec(body["adaptive"], scenes.limits.max_points);
  plan.adaptive_phi = phi[0];
  plan.seeds = scenes.seeds;
  const std::size_t n_initial = adaptive::initial_points(*plan.adaptive).size();
  const auto initial = adaptive::next_points(*plan.adaptive, {}, {}, n_initial);
  plan.levels = level_scenes(body, base, phi[0], initial.front(), scenes.limits);
  // The initial grid in the planner's order (cheapest first, as every later point): the
  // queue runs a sweep's jobs in the order they were added. One run a point: replicates and
  // finer levels follow where the map asks for them.
  double initial_cpu = 0;
  for (const adaptive::Point& pt : initial) {
    SceneParams p = make_scene(plan.levels.front(), pt.S, pt.R, phi[0], "", scenes.limits);
    if (!plan.seeds.empty()) p.seed = plan.seeds.front();
    initial_cpu += cost::cpu_seconds(p);
    scenes.add_one(std::move(p));
  }
  plan.budget_cpu_seconds = cpu_budget(body["adaptive"], initial_cpu);
  // The stored request says what the sweep does: the defaults it took written in.
  json& spec = plan.request["adaptive"];
  spec["initial"] = {{"S", plan.adaptive->initial_S}, {"R", plan.adaptive->initial_R}};
  spec["resolution_decades"] = plan.adaptive->resolution_decades;
  spec["budget"] = plan.adaptive->budget;
}

// An explicit list of points, each {S, R, phi}.
void plan_points(const json& points, const SceneParams& base, SceneList& scenes) {
  if (!points.is_array()) invalid("points", "must be an array, got " + describe(points));
  if (points.empty()) invalid("points", "must not be empty");
  if (points.size() > scenes.limits.max_points) {
    invalid("points", std::to_string(points.size()) + " points exceed the sweep limit of " +
                          std::to_string(scenes.limits.max_points), 413);
  }
  scenes.check_count(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "].";
    const json& pt = points[i];
    if (!pt.is_object()) invalid("points[" + std::to_string(i) + "]", "must be an object");
    for (const auto& [key, value] : pt.items()) {
      if (key != "S" && key != "R" && key != "phi") invalid(where + key, "unknown key");
    }
    scenes.add(make_scene(base, point_value(pt, "S", where), point_value(pt, "R", where),
                          point_value(pt, "phi", where), where, scenes.limits));
  }
}

// A grid over S, R and phi, S fastest.
void plan_grid(const json& body, const SceneParams& base, SceneList& scenes) {
  const std::size_t max_points = scenes.limits.max_points;
  for (const char* key : {"S", "R", "phi"}) {
    if (!body.contains(key)) invalid(key, "is required for a grid");
  }
  const auto S = expand_axis(body["S"], "S", max_points);
  const auto R = expand_axis(body["R"], "R", max_points);
  const auto phi = expand_axis(body["phi"], "phi", max_points);
  const double total = static_cast<double>(S.size()) * R.size() * phi.size();
  if (total > static_cast<double>(max_points)) {
    const char* biggest = S.size() >= R.size() && S.size() >= phi.size() ? "S"
                          : R.size() >= phi.size()                      ? "R"
                                                                        : "phi";
    invalid(biggest, "a grid of " + std::to_string(S.size()) + " x " + std::to_string(R.size()) +
                         " x " + std::to_string(phi.size()) + " points exceeds the sweep limit of " +
                         std::to_string(max_points), 413);
  }
  scenes.check_count(static_cast<std::size_t>(total));
  for (double f : phi) {
    for (double r : R) {
      for (double s : S) {
        // Grid errors name the axis ("S") rather than a point.
        scenes.add(make_scene(base, s, r, f, "", scenes.limits));
      }
    }
  }
}

}  // namespace

SweepPlan plan_sweep(const json& body, const PlannerLimits& limits) {
  if (!body.is_object()) invalid("body", "must be a JSON object", 400);
  for (const auto& [key, value] : body.items()) {
    if (!request_keys.count(key)) invalid(key, "unknown key");
  }
  SweepPlan plan;
  plan.request = body;
  read_header(body, limits, plan);
  std::vector<std::uint64_t> seeds;
  const SceneParams base = base_scene(body, plan.preset, seeds);
  SceneList scenes{plan, seeds, limits, {}};
  plan.replicates = scenes.per_point();

  if (body.contains("adaptive")) {
    plan_adaptive(body, base, scenes);
    return plan;
  }
  const bool has_points = body.contains("points");
  const bool has_grid = body.contains("S") || body.contains("R") || body.contains("phi");
  if (has_points && has_grid) invalid("points", "give either points or a grid (S, R, phi), not both");
  if (!has_points && !has_grid) invalid("points", "give points or a grid over S, R and phi");
  if (has_points) {
    plan_points(body["points"], base, scenes);
  } else {
    plan_grid(body, base, scenes);
  }
  return plan;
}

}  // namespace compaction::server
