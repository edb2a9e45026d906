// A point's replicates read together (docs/replicates.md). A point is a computation up to its
// seed (migration 0011): its runs differ only in the particles' perturbation or the random
// structure the seed draws, so they are draws of one random outcome, and the map shows what
// they say together: how often each class came out, the majority and its share, and each
// band-speed reading's mean and spread. A point of one run reads as that run.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plan/adaptive_plan.hpp"

namespace compaction::server {

struct Tally {
  std::size_t runs = 0;      // the point's replicates, finished or not
  std::size_t finished = 0;  // of those, finished (succeeded, failed for good or cancelled)
  std::size_t labelled = 0;  // of those, with a counted label (counted_label.hpp)
  // Each class's share of the labelled runs, in class order; empty without a label.
  std::vector<std::pair<std::string, double>> probabilities;
  // The majority's label and share. A tie goes to the class whose runs' confidences sum
  // higher, then to the earlier class: the share (0.5 for a 2:2 split) says how weak it is.
  std::optional<std::string> label;
  double share = 0;
  // Every replicate finished with the same label, and there are at least two: the label held
  // under the perturbation. One run has no evidence either way, so it is never robust.
  bool robust = false;
  // The point as the adaptive planner reads one run: the majority, with confidence
  // share x the mean confidence of the majority's runs, and the runner-up the second most
  // frequent class (when the replicates agree: their most frequent runner-up).
  adaptive::Labelled as_run{};
};

// finished: the counted labels of the finished replicates (a failed or unclassified one has
// none); runs: all replicates of the point, pending ones included (runs >= finished.size()).
Tally tally(adaptive::Point point, const std::vector<adaptive::Labelled>& finished, std::size_t runs);

// Mean, standard deviation (with n - 1; none for one value) and count of a reading over the
// replicates that have it; nullopt when none has.
struct Spread {
  double mean = 0;
  std::optional<double> sd;
  std::size_t n = 0;
};
std::optional<Spread> spread(const std::vector<double>& values);

}  // namespace compaction::server
