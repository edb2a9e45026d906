// Which label of a finished run counts (docs/service.md, "Human labels"): a person's where there
// is one, certain (confidence 1), with the classifier's label as the runner-up; otherwise the
// classifier's, with its confidence and runner-up. The adaptive planner and the predicted regions
// both read a run's label through here, so the map's background and its refinement agree with
// the markers the dashboard draws.
#pragma once

#include <optional>
#include <string>

#include "plan/adaptive_plan.hpp"

namespace compaction::server {

inline adaptive::Labelled counted_label(adaptive::Point point, const std::optional<std::string>& human,
                                        const std::optional<std::string>& classifier,
                                        std::optional<double> confidence,
                                        const std::optional<std::string>& runner_up) {
  if (human) return {point, human, 1.0, classifier};
  return {point, classifier, confidence.value_or(0.0), runner_up};
}

}  // namespace compaction::server
