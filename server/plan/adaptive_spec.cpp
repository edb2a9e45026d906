#include "plan/adaptive_plan.hpp"

#include <cmath>
#include <set>
#include <tuple>

#include "compaction/number_text.hpp"
#include "compaction/params.hpp"
#include "input/api_error.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"

// An adaptive request's "adaptive" object read into its spec (adaptive_plan.hpp): the fields,
// their defaults and the 4xx of each. The planning itself is adaptive_plan.cpp's.
namespace compaction::server::adaptive {

using nlohmann::json;
using text::num;

namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& message, int status = 422) {
  throw ApiError(status, field, message);
}

void only_keys(const json& obj, const std::string& field, const std::set<std::string>& keys) {
  std::string list;
  for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
  for (const auto& [key, value] : obj.items()) {
    if (!keys.count(key)) invalid(field + "." + key, "unknown key (expected " + list + ")");
  }
}

const json& required(const json& obj, const std::string& field, const char* key) {
  if (!obj.contains(key)) invalid(field + "." + key, "is required");
  return obj[key];
}

double finite_in(const json& v, const std::string& field, const Range& range) {
  if (!v.is_number() || !std::isfinite(v.get<double>())) {
    invalid(field, "must be a finite number, got " + describe(v));
  }
  const double x = v.get<double>();
  if (!range.contains(x)) invalid(field, "must be in " + to_string(range) + ", got " + num(x));
  return x;
}

AxisRange parse_axis(const json& a, const std::string& field, const Range& range) {
  if (!a.is_object()) invalid(field, "must be an object {min, max}, got " + describe(a));
  only_keys(a, field, {"min", "max"});
  AxisRange r;
  r.min = finite_in(required(a, field, "min"), field + ".min", range);
  r.max = finite_in(required(a, field, "max"), field + ".max", range);
  if (!(r.max > r.min)) invalid(field + ".max", "must be > min (" + num(r.min) + "), got " + num(r.max));
  return r;
}

long long integer_at_least(const json& v, const std::string& field, long long lo) {
  if (!v.is_number_integer()) invalid(field, "must be an integer, got " + describe(v));
  const auto i = as_int64(v);
  if (!i || *i < lo) invalid(field, "must be at least " + std::to_string(lo) + ", got " + describe(v));
  return *i;
}

double decades(const AxisRange& a) { return std::log10(a.max) - std::log10(a.min); }

}  // namespace

AdaptiveSpec parse_spec(const json& a, std::size_t max_points, const std::string& field) {
  if (!a.is_object()) invalid(field, "must be an object, got " + describe(a));
  // levels and budget_cpu_hours name scenes: the planner reads them (planner.cpp).
  only_keys(a, field, {"S", "R", "initial", "resolution_decades", "budget", "in_flight", "levels",
                       "budget_cpu_hours"});
  AdaptiveSpec spec;
  spec.S = parse_axis(required(a, field, "S"), field + ".S", limits::S);
  spec.R = parse_axis(required(a, field, "R"), field + ".R", limits::R);

  const std::string f_initial = field + ".initial";
  const json initial = a.value("initial", json{{"S", kDefaultInitialPerAxis}, {"R", kDefaultInitialPerAxis}});
  if (!initial.is_object()) invalid(f_initial, "must be an object {S, R}, got " + describe(initial));
  only_keys(initial, f_initial, {"S", "R"});
  const long long nS = integer_at_least(required(initial, f_initial, "S"), f_initial + ".S", kMinInitialPerAxis);
  const long long nR = integer_at_least(required(initial, f_initial, "R"), f_initial + ".R", kMinInitialPerAxis);
  const auto max = static_cast<long long>(max_points);
  if (nS > max || nR > max || nS * nR > max) {
    invalid(nS >= nR ? f_initial + ".S" : f_initial + ".R",
            "an initial grid of " + std::to_string(nS) + " x " + std::to_string(nR) +
                " points exceeds the sweep limit of " + std::to_string(max_points) + " points",
            413);
  }
  spec.initial_S = static_cast<int>(nS);
  spec.initial_R = static_cast<int>(nR);

  const std::string f_res = field + ".resolution_decades";
  const json res = a.value("resolution_decades", json(kDefaultResolutionDecades));
  if (!res.is_number() || !std::isfinite(res.get<double>())) {
    invalid(f_res, "must be a finite number, got " + describe(res));
  }
  spec.resolution_decades = res.get<double>();
  if (!(spec.resolution_decades >= kFinestResolutionDecades)) {
    invalid(f_res, "must be at least " + num(kFinestResolutionDecades) + " (1/64 decade), got " +
                       num(spec.resolution_decades));
  }
  for (const auto& [axis, range, n] : {std::tuple{"S", spec.S, nS}, std::tuple{"R", spec.R, nR}}) {
    const double step = decades(range) / static_cast<double>(n - 1);
    if (spec.resolution_decades > step * (1 + kStepSlack)) {
      invalid(f_res, std::string("must be at most the initial grid's step in ") + axis + " (" +
                         num(step) + " decades), got " + num(spec.resolution_decades));
    }
  }

  const std::string f_budget = field + ".budget";
  const long long budget = integer_at_least(
      a.value("budget", json(std::max(nS * nR, std::min(kDefaultBudget, max)))), f_budget, nS * nR);
  if (budget > max) {
    invalid(f_budget, std::to_string(budget) + " runs exceed the sweep limit of " +
                          std::to_string(max_points) + " points", 413);
  }
  spec.budget = static_cast<std::size_t>(budget);
  if (a.contains("in_flight")) {
    const std::string f_in_flight = field + ".in_flight";
    const long long n = integer_at_least(a["in_flight"], f_in_flight, 1);
    if (n > budget) {
      invalid(f_in_flight, "must be at most the budget (" + std::to_string(budget) + "), got " +
                               std::to_string(n));
    }
    spec.in_flight = static_cast<std::size_t>(n);
  }
  return spec;
}

}  // namespace compaction::server::adaptive
