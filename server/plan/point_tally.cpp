#include "plan/point_tally.hpp"

namespace compaction::server {

Tally tally(adaptive::Point point, const std::vector<adaptive::Labelled>& finished, std::size_t runs) {
  std::vector<Vote> votes;
  votes.reserve(finished.size());
  for (const adaptive::Labelled& r : finished) votes.push_back({r.label, r.confidence, r.runner_up});
  const PointVote v = vote(votes, runs);
  Tally t;
  t.runs = v.runs;
  t.finished = finished.size();
  t.labelled = v.labelled;
  t.probabilities = v.probabilities;
  t.label = v.label;
  t.share = v.share;
  t.robust = v.robust;
  t.as_run = {point, v.label, v.confidence, v.runner_up};
  return t;
}

}  // namespace compaction::server
