#include "plan/planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "compaction/bundle.hpp"
#include "compaction/number_text.hpp"
#include "compaction/params_json.hpp"
#include "compaction/presets.hpp"
#include "input/api_error.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"
#include "plan/round_significant.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// Numerics keys a sweep may set (the rest of SceneParams is fixed by the model or per point).
const std::set<std::string> numerics_keys = {
    "preset", "cells_per_strut", "cells_per_unit", "particles_per_cell", "cfl", "transfer",
    "movie_d_eps",
    "flip_ratio", "eps_end", "d_eps", "snapshot_eps", "contact", "pore_contact", "perturbation", "seed",
    "structure", "seeds"};

const std::set<std::string> request_keys = {"name", "points", "S", "R", "phi", "numerics",
                                            "priority", "max_attempts", "adaptive"};

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

// The scene every point starts from: preset, then the explicit numerics over it; `seeds` the
// seeds of numerics.seeds (empty without it: each point runs once with the scene's seed).
SceneParams base_scene(const json& body, std::string& preset_name,
                       std::vector<std::uint64_t>& seeds) {
  json numerics = json::object();
  if (body.contains("numerics")) {
    numerics = body["numerics"];
    if (!numerics.is_object()) invalid("numerics", "must be an object, got " + describe(numerics));
  }
  for (const auto& [key, value] : numerics.items()) {
    if (!numerics_keys.count(key)) invalid("numerics." + key, "unknown numerics key");
  }
  seeds.clear();
  if (numerics.contains("seeds")) {
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
  SceneParams scene;
  // The preset's values, then the explicit keys over them. Here only their types: the ranges
  // (some depend on phi) are validated once, per point, with the point's S, R and phi.
  json merged = compaction::preset_json(*compaction::find_preset(preset_name));
  for (const auto& [key, value] : numerics.items()) merged[key] = value;
  merged["threads"] = 1;
  if (std::vector<FieldError> errors = read_json(merged, scene); !errors.empty()) {
    std::vector<FieldError> named;
    for (auto& e : errors) named.push_back({"numerics." + e.field, e.message});
    throw ApiError(422, std::move(named));
  }
  if (seeds.size() > 1 && scene.structure == Structure::regular && scene.perturbation == 0.0) {
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

std::vector<SceneParams> adaptive_scenes(const SweepPlan& plan,
                                         const std::vector<adaptive::Point>& points,
                                         const PlannerLimits& limits) {
  std::string preset;
  std::vector<std::uint64_t> seeds;
  SceneParams base = base_scene(plan.request, preset, seeds);
  if (!seeds.empty()) base.seed = seeds.front();  // an adaptive sweep takes one seed
  const double phi = plan.scenes.empty() ? base.phi : plan.scenes.front().phi;
  std::vector<SceneParams> out;
  for (const adaptive::Point& pt : points) out.push_back(make_scene(base, pt.S, pt.R, phi, "", limits));
  return out;
}

SweepPlan plan_sweep(const json& body, const PlannerLimits& limits) {
  if (!body.is_object()) invalid("body", "must be a JSON object", 400);
  for (const auto& [key, value] : body.items()) {
    if (!request_keys.count(key)) invalid(key, "unknown key");
  }
  SweepPlan plan;
  plan.request = body;

  if (!body.contains("name")) invalid("name", "is required");
  if (!body["name"].is_string()) invalid("name", "must be a string, got " + describe(body["name"]));
  plan.name = body["name"].get<std::string>();
  if (plan.name.empty() || plan.name.size() > kMaxNameBytes) {
    invalid("name", "must be 1 to " + std::to_string(kMaxNameBytes) + " bytes");
  }
  if (has_control_characters(plan.name)) invalid("name", "must not hold control characters");
  plan.priority = integer_in(body, "priority", kDefaultPriority, kPriorityMin, kPriorityMax);
  plan.max_attempts = integer_in(body, "max_attempts", kDefaultMaxAttempts, 1, limits.max_attempts);

  std::vector<std::uint64_t> seeds;
  const SceneParams base = base_scene(body, plan.preset, seeds);
  // Each point once per seed of numerics.seeds, in the order given (else once).
  const std::size_t per_point = std::max<std::size_t>(1, seeds.size());
  auto check_count = [&](std::size_t points) {
    if (per_point > 1 && static_cast<double>(points) * per_point > limits.max_points) {
      invalid("numerics.seeds", std::to_string(points) + " points x " + std::to_string(per_point) +
                                    " seeds exceed the sweep limit of " +
                                    std::to_string(limits.max_points) + " runs", 413);
    }
  };

  const bool has_points = body.contains("points");
  std::set<std::string> seen;
  auto add_one = [&](SceneParams p) {
    if (seen.insert(canonical_scene(p)).second) plan.scenes.push_back(std::move(p));
  };
  auto add = [&](SceneParams p) {
    if (seeds.empty()) return add_one(std::move(p));
    for (std::uint64_t seed : seeds) {
      p.seed = seed;
      add_one(p);
    }
  };

  if (body.contains("adaptive")) {
    // A box of S and R at one phi, from which the sweep grows (adaptive_plan.hpp).
    for (const char* key : {"points", "S", "R"}) {
      if (body.contains(key)) {
        invalid(key, "an adaptive sweep takes its S and R box inside \"adaptive\", not beside it");
      }
    }
    if (!body.contains("phi")) invalid("phi", "is required: an adaptive sweep maps one phi");
    const auto phi = expand_axis(body["phi"], "phi", limits.max_points);
    if (phi.size() != 1) {
      invalid("phi", "an adaptive sweep maps one phi, got " + std::to_string(phi.size()) + " values");
    }
    if (seeds.size() > 1) {
      invalid("numerics.seeds", "an adaptive sweep maps one structure: give one seed "
                                "(numerics.seed), got " + std::to_string(seeds.size()));
    }
    plan.adaptive = adaptive::parse_spec(body["adaptive"], limits.max_points);
    // The stored request says what the sweep does: the defaults it took written in.
    json& spec = plan.request["adaptive"];
    spec["initial"] = {{"S", plan.adaptive->initial_S}, {"R", plan.adaptive->initial_R}};
    spec["resolution_decades"] = plan.adaptive->resolution_decades;
    spec["budget"] = plan.adaptive->budget;
    // The initial grid in the planner's order (cheapest first, as every later point): the
    // queue runs a sweep's jobs in the order they were added.
    const std::size_t n_initial = adaptive::initial_points(*plan.adaptive).size();
    for (const adaptive::Point& pt : adaptive::next_points(*plan.adaptive, {}, {}, n_initial)) {
      add(make_scene(base, pt.S, pt.R, phi[0], "", limits));
    }
    return plan;
  }

  const bool has_grid = body.contains("S") || body.contains("R") || body.contains("phi");
  if (has_points && has_grid) invalid("points", "give either points or a grid (S, R, phi), not both");
  if (!has_points && !has_grid) invalid("points", "give points or a grid over S, R and phi");
  if (has_points) {
    const json& points = body["points"];
    if (!points.is_array()) invalid("points", "must be an array, got " + describe(points));
    if (points.empty()) invalid("points", "must not be empty");
    if (points.size() > limits.max_points) {
      invalid("points", std::to_string(points.size()) + " points exceed the sweep limit of " +
                            std::to_string(limits.max_points), 413);
    }
    check_count(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::string where = "points[" + std::to_string(i) + "].";
      const json& pt = points[i];
      if (!pt.is_object()) invalid("points[" + std::to_string(i) + "]", "must be an object");
      for (const auto& [key, value] : pt.items()) {
        if (key != "S" && key != "R" && key != "phi") invalid(where + key, "unknown key");
      }
      add(make_scene(base, point_value(pt, "S", where), point_value(pt, "R", where),
                     point_value(pt, "phi", where), where, limits));
    }
    return plan;
  }

  for (const char* key : {"S", "R", "phi"}) {
    if (!body.contains(key)) invalid(key, "is required for a grid");
  }
  const auto S = expand_axis(body["S"], "S", limits.max_points);
  const auto R = expand_axis(body["R"], "R", limits.max_points);
  const auto phi = expand_axis(body["phi"], "phi", limits.max_points);
  const double total = static_cast<double>(S.size()) * R.size() * phi.size();
  if (total > static_cast<double>(limits.max_points)) {
    const char* biggest = S.size() >= R.size() && S.size() >= phi.size() ? "S"
                          : R.size() >= phi.size()                      ? "R"
                                                                        : "phi";
    invalid(biggest, "a grid of " + std::to_string(S.size()) + " x " + std::to_string(R.size()) +
                         " x " + std::to_string(phi.size()) + " points exceeds the sweep limit of " +
                         std::to_string(limits.max_points), 413);
  }
  check_count(static_cast<std::size_t>(total));
  for (double f : phi) {
    for (double r : R) {
      for (double s : S) {
        // Grid errors name the axis ("S") rather than a point.
        add(make_scene(base, s, r, f, "", limits));
      }
    }
  }
  return plan;
}

}  // namespace compaction::server
