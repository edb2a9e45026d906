// Adaptive sweeps: where to run next on the map of S and R (both on log scales) at one phi,
// given the labels already known. Pure functions of their arguments: the caller passes the
// sweep's spec, its finished runs and its queued ones, and gets the points to queue next.
//
//   "adaptive": {"S": {"min": 1e-3, "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1},
//                "initial": {"S": 5, "R": 5}, "resolution_decades": 0.125, "budget": 200,
//                "in_flight": 8}
//
// The rule (docs/adaptive.md): the initial grid's cells form the roots of a quadtree in
// (log10 S, log10 R). A cell whose four corners have results and whose boundary points disagree
// (different labels, a label next to an unknown one, or a low confidence) is split at its
// midpoints until its sides reach the finest step, the initial step halved while it stays at
// least resolution_decades. A new point is worth weight x size of the cell that asks for it
// (the largest, if several do); the most valuable come first, and at equal value the cheaper
// (larger S: a run costs about 1/S).
#pragma once

#include <compare>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace compaction::server::adaptive {

// Limits of a spec, beyond the scene's ranges of S and R (compaction::limits) and the sweep
// limit (PlannerLimits::max_points), which bounds the budget.
inline constexpr double kFinestResolutionDecades = 1.0 / 64;  // a 3.7 % step in S or R
inline constexpr long long kMinInitialPerAxis = 2;            // the box's two corners
// A request's defaults for what it leaves out (GET /api/v1/limits serves them to the form and
// the Python client): 5 x 5 initial points, an eighth of a decade (the example of
// docs/adaptive.md, whose straight boundary across the box took 92 runs and three regions
// meeting 134), and a budget of 200 runs (or the sweep limit, when lower).
inline constexpr long long kDefaultInitialPerAxis = 5;
inline constexpr double kDefaultResolutionDecades = 0.125;
inline constexpr long long kDefaultBudget = 200;
// The most levels of numerics an adaptive sweep may name ("levels", levels_plan.hpp).
inline constexpr std::size_t kMaxLevels = 4;
// Relative slack of comparisons between steps and the resolution: far above the rounding of
// values to 12 significant digits, far below a step.
inline constexpr double kStepSlack = 1e-9;

// Weights of a cell's disagreement (value = weight x the cell's longer side in decades).
// Two labels differ: the boundary the map is drawn for.
inline constexpr double kWeightLabelsDiffer = 1.0;
// A label next to an unknown one (a failed or unclassified run): the edge of the region without
// a label is drawn on the map too, but a run may also fail for reasons of its own, so these
// come after real boundaries of the same size.
inline constexpr double kWeightUnknown = 0.5;
// The same label everywhere, but a confidence below kConfidentFrom: the runner-up class scored
// nearly as well, so its region may be close (an island the coarse grid stepped over). Weighted
// by (1 - confidence / kConfidentFrom), so a confidence of 0 weighs as much as an unknown.
inline constexpr double kWeightLowConfidence = 0.5;
// The classifier's confidence is the gap between the best and the runner-up score (both in
// [0, 1]); a gap of a quarter of the range is taken as a clear verdict.
inline constexpr double kConfidentFrom = 0.25;

// Points of a sweep queued or running at once when the request does not say ("in_flight"):
// the cores of a workstation or two.
inline constexpr std::size_t kDefaultInFlight = 8;

struct AxisRange {
  double min = 0, max = 0;  // 0 < min < max < 1
};

struct AdaptiveSpec {
  AxisRange S, R;                 // the box; the map is planned on log10 S and log10 R
  int initial_S = 0, initial_R = 0;  // initial grid: points per axis, log-spaced, ends included
  double resolution_decades = 0;  // the finest step wanted, in decades, on both axes
  std::size_t budget = 0;         // the most runs the sweep may hold, the initial grid included
  // The most points queued or running at once, past the initial grid: the runs the workers
  // can do in parallel. Fewer mean each new point is chosen knowing more results.
  std::size_t in_flight = kDefaultInFlight;
};

// The spec from the request's "adaptive" object: S and R required, the rest with the defaults
// above. Errors are ApiError naming the field under `field` ("adaptive.S.min",
// "adaptive.budget"): 422 for invalid values, 413 for a budget above max_points (the server's
// sweep limit). "levels" and "budget_cpu_hours" are let through for the planner, which reads
// them with the sweep's scenes (planner.cpp). Defined in adaptive_spec.cpp.
AdaptiveSpec parse_spec(const nlohmann::json& adaptive, std::size_t max_points,
                        const std::string& field = "adaptive");

struct Point {
  double S = 0, R = 0;
  bool operator==(const Point&) const = default;
};

struct Labelled {
  Point point;
  std::optional<std::string> label;      // "a".."f"; none for a failed or unclassified run
  double confidence = 0;                 // in [0, 1]; read only when there is a label
  std::optional<std::string> runner_up;  // the second best class (carried for the caller)
  // The run's share of its point's weight where a point's replicates vote together (the
  // predicted regions, phase_regions.hpp: 1 / the point's labelled runs); 1 elsewhere.
  double share = 1;
};

struct Proposal {
  Point point;
  double value = 0;  // weight x cell size; the initial grid's points exceed any cell's
};

// The finest step of each axis in decades: the initial step halved while it stays
// >= resolution_decades, so in [resolution_decades, 2 resolution_decades).
struct Steps {
  double S = 0, R = 0;
};
Steps finest_steps(const AdaptiveSpec& spec);

// The initial grid, R outer and S inner (the order of a grid sweep): the values of
// planner's expand_axis with scale "log" (rounded to 12 significant digits, ends exact), so a
// grid sweep of the same box shares its jobs.
std::vector<Point> initial_points(const AdaptiveSpec& spec);

// Every point worth running now, best first: highest value, then larger S (cheaper), then
// smaller R. Excludes points in done or pending, points closer than resolution_decades (on both
// axes at once) to any of them, and points around a pending one (cells with a corner still
// queued wait for its result). Ignores the budget. The order of the inputs does not matter;
// given points off the lattice (or outside the box) only keep proposals away, their labels are
// not read.
std::vector<Proposal> ranked_candidates(const AdaptiveSpec& spec, const std::vector<Labelled>& done,
                                        const std::vector<Point>& pending);

// The first how_many of ranked_candidates, and no more than the budget leaves:
// done.size() + pending.size() + result.size() <= spec.budget. Empty when there is nothing
// worth running (or until pending results arrive). A point in done is never proposed again,
// failed or not: retries are the queue's business.
std::vector<Point> next_points(const AdaptiveSpec& spec, const std::vector<Labelled>& done,
                               const std::vector<Point>& pending, std::size_t how_many);

// The node of the finest lattice a point sits on (i finest steps along log S and j along log R
// from the box's lower corner), if it sits on one inside the box; and the point of a node,
// none outside the box. The levels planner (levels_plan.hpp) walks the lattice with these.
struct LatticeNode {
  long long i = 0, j = 0;
  auto operator<=>(const LatticeNode&) const = default;
};
std::optional<LatticeNode> lattice_node(const AdaptiveSpec& spec, Point p);
// An initial cell's sides and the box's, in finest steps (the quadtree's roots and its extent).
struct LatticeShape {
  long long width_S = 1, width_R = 1, nodes_S = 0, nodes_R = 0;
};
LatticeShape lattice_shape(const AdaptiveSpec& spec);
std::optional<Point> lattice_point(const AdaptiveSpec& spec, LatticeNode n);

// Whether the boundaries are found to the finest step: every initial point is done and no cell
// whose labels disagree (two labels, or a label and an unknown) is still larger than the finest
// step. Low confidence alone does not keep a map unresolved.
bool resolved(const AdaptiveSpec& spec, const std::vector<Labelled>& done);

}  // namespace compaction::server::adaptive
