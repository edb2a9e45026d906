// A map that measures its own trust (docs/adaptive.md, "Levels and replicates"): an adaptive
// sweep with levels of numerics, coarse to fine, and up to n replicates of a point per level.
// Pure functions of their arguments, beside adaptive_plan.hpp, whose quadtree they use for the
// coarsest level.
//
// The rule, in the order its actions rank:
//  1. Map with the coarsest level as adaptive_plan does (one run per point, or its replicates:
//     a point is read by the majority of its runs at a level, point_tally.hpp).
//  2. Where the map at a level has a boundary (a cell of the finest lattice whose four corners
//     are known at that level and disagree), or a point whose confidence is low: replicates,
//     up to n, at that level, so that the boundary is not a perturbation's accident.
//  3. Where a boundary still lies after its replicates, or where a point's replicates disagree:
//     the next level, starting with one run.
//  4. Where a point's label changed between two levels (the boundary moved with the
//     resolution): the points around it at the finer level too, so that the finer level's
//     boundary is followed to where it is, not where the coarser one put it.
// It stops refining a point once the finest level's replicates agree or the budgets, in runs
// and in CPU-hours by the cost model, are spent. A point's label is that of its finest level
// whose runs have all finished; it records whether its label changed between levels.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "plan/adaptive_plan.hpp"
#include "plan/point_tally.hpp"

namespace compaction::server::adaptive {

// Weights of the trust actions (step 2 to 4), times the finest step in decades: all rank below
// the coarsest level's map (step 1, whose values are at least kWeightLabelsDiffer x the finest
// step), and within them a coarser level first (its runs are cheaper and decide where the
// finer one goes), then by weight, then the cheaper run.
inline constexpr double kWeightBoundaryReplicate = 1.0;  // a replicate of a boundary point
inline constexpr double kWeightLevelUp = 1.0;            // a boundary point at the next level
inline constexpr double kWeightFollow = 1.0;             // around a point whose label moved
inline constexpr double kWeightUnsureReplicate = 0.5;    // a replicate of a low-confidence point

struct LevelsSpec {
  AdaptiveSpec box;            // the box, the coarsest level's initial grid and resolution;
                               // box.budget and box.in_flight count runs of every level
  int levels = 1;              // numbered 0 (coarsest) to levels - 1 (finest)
  std::size_t replicates = 1;  // the most runs of a point at one level (seeds 1..n)
  double budget_cpu_seconds = std::numeric_limits<double>::infinity();
};

struct LevelRun {  // a finished run
  Point point;
  int level = 0;
  std::optional<std::string> label;  // none: failed or unclassified
  double confidence = 0;
  std::optional<std::string> runner_up;
};

struct LevelQueued {  // a run queued or running
  Point point;
  int level = 0;
};

struct LevelAction {
  Point point;
  int level = 0;
  std::size_t replicate = 0;  // the point's runs at this level before it: its seed is this + 1
  double value = 0;
  double cpu_seconds = 0;     // the cost model's, for this run
  const char* why = "";       // "map", "replicate", "level", "follow", "unsure"
};

// The CPU seconds of one run of a point at a level (server/plan/cost_model.hpp).
using RunCost = std::function<double(Point, int)>;

// Every action worth taking now, best first (ranked as above); ignores the budgets.
std::vector<LevelAction> ranked_level_actions(const LevelsSpec& spec, const std::vector<LevelRun>& done,
                                              const std::vector<LevelQueued>& pending,
                                              const RunCost& cost);

// The first how_many of them that fit the budgets: runs done + pending + taken <= box.budget
// and their CPU seconds <= budget_cpu_seconds (an action that does not fit is passed over for
// a cheaper one).
std::vector<LevelAction> next_level_actions(const LevelsSpec& spec, const std::vector<LevelRun>& done,
                                            const std::vector<LevelQueued>& pending,
                                            const RunCost& cost, std::size_t how_many);

// Whether the finest level's boundaries are found: the coarsest level's map is resolved, and no
// boundary, disagreeing point or moved label asks for a replicate or a finer level.
bool levels_resolved(const LevelsSpec& spec, const std::vector<LevelRun>& done, const RunCost& cost);

// What the sweep says of each point of the lattice it ran: its label (the finest level whose
// runs have all finished), that level's tally, and whether the label changed between levels.
struct NodeLabel {
  Point point;
  int level = 0;
  Tally tally;
  bool changed = false;
};
std::vector<NodeLabel> node_labels(const LevelsSpec& spec, const std::vector<LevelRun>& done);

}  // namespace compaction::server::adaptive
