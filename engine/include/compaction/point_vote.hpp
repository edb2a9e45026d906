// A point's replicates read together (docs/replicates.md). A point is a computation up to its
// seed: its runs differ only in the particles' perturbation or the random structure the seed
// draws, so they are draws of one random outcome, and what they say together is how often each
// class came out, the majority and its share, and each reading's mean and spread over the
// majority's runs. A point of one run reads as that run. The server's map (its points and
// their planning) and compaction-classify's reading of several bundles both vote here.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "compaction/params.hpp"

namespace compaction {

// One finished replicate as it votes: its label ("a".."f"; none for a failed or unclassified
// run), the classifier's confidence in it and its runner-up.
struct Vote {
  std::optional<std::string> label;
  double confidence = 0;
  std::optional<std::string> runner_up;
};

struct PointVote {
  std::size_t runs = 0;      // the point's replicates, finished or not
  std::size_t labelled = 0;  // of the finished ones, those with a label
  // Each class's share of the labelled runs, in class order; empty without a label.
  std::vector<std::pair<std::string, double>> probabilities;
  // The majority's label and share. A tie goes to the class whose runs' confidences sum
  // higher, then to the earlier class: the share (0.5 for a 2:2 split) says how weak it is.
  std::optional<std::string> label;
  double share = 0;
  // Every replicate finished with the same label, and there are at least two: the label held
  // under the perturbation. One run has no evidence either way, so it is never robust.
  bool robust = false;
  // The point read as one run: confidence = share x the mean confidence of the majority's runs;
  // runner-up = the second most frequent class (when the replicates agree: their most frequent
  // runner-up).
  double confidence = 0;
  std::optional<std::string> runner_up;
};

// finished: the votes of the finished replicates; runs: all replicates of the point, pending
// ones included (runs below finished.size() count as finished.size()).
PointVote vote(const std::vector<Vote>& finished, std::size_t runs);

// Mean, standard deviation (with n - 1; none for one value) and count of a reading over the
// replicates that have it; nullopt when none has.
struct Spread {
  double mean = 0;
  std::optional<double> sd;
  std::size_t n = 0;
};
std::optional<Spread> spread(const std::vector<double>& values);

// Whether two scenes are replicates of one point: equal but for their seed (the server's key of
// a point is the same, in SQL: schema/migrations/0011_points.sql). The name of the first key
// that differs, or nullopt when they are one point.
std::optional<std::string> differs_beyond_seed(const SceneParams& a, const SceneParams& b);

}  // namespace compaction
