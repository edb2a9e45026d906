// A point's replicates read together for the map and the planner: the vote of its finished
// runs (compaction/point_vote.hpp, the rule's home, shared with compaction-classify) and the
// point read as one run for the adaptive planner. A point is a computation up to its seed
// (migration 0011).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compaction/point_vote.hpp"
#include "plan/adaptive_plan.hpp"

namespace compaction::server {

using compaction::Spread;
using compaction::spread;

struct Tally {
  std::size_t runs = 0;      // the point's replicates, finished or not
  std::size_t finished = 0;  // of those, finished (succeeded, failed for good or cancelled)
  std::size_t labelled = 0;  // of those, with a counted label (counted_label.hpp)
  // The vote's reading (point_vote.hpp): each class's share in class order, the majority and
  // its share, robust when at least two replicates all agree.
  std::vector<std::pair<std::string, double>> probabilities;
  std::optional<std::string> label;
  double share = 0;
  bool robust = false;
  // The point as the adaptive planner reads one run: the majority, with the vote's confidence
  // and runner-up.
  adaptive::Labelled as_run{};
};

// finished: the counted labels of the finished replicates (a failed or unclassified one has
// none); runs: all replicates of the point, pending ones included (runs >= finished.size()).
Tally tally(adaptive::Point point, const std::vector<adaptive::Labelled>& finished, std::size_t runs);

}  // namespace compaction::server
