#include "plan/point_tally.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace compaction::server {

namespace {

struct ClassCount {
  std::size_t n = 0;
  double confidence = 0;  // summed over the class's runs
};

// The most frequent of a list of labels (ties: the earlier in class order); nullopt for none.
std::optional<std::string> most_frequent(const std::map<std::string, std::size_t>& counts) {
  std::optional<std::string> best;
  std::size_t best_n = 0;
  for (const auto& [label, n] : counts) {
    if (n > best_n) best = label, best_n = n;
  }
  return best;
}

}  // namespace

Tally tally(adaptive::Point point, const std::vector<adaptive::Labelled>& finished, std::size_t runs) {
  Tally t;
  t.runs = std::max(runs, finished.size());
  t.finished = finished.size();
  std::map<std::string, ClassCount> classes;  // ordered: class order
  for (const adaptive::Labelled& r : finished) {
    if (!r.label) continue;
    ++t.labelled;
    ClassCount& c = classes[*r.label];
    ++c.n;
    c.confidence += r.confidence;
  }
  t.as_run = {point, std::nullopt, 0.0, std::nullopt};
  if (t.labelled == 0) return t;

  const ClassCount* top = nullptr;
  for (const auto& [label, c] : classes) {
    t.probabilities.emplace_back(label, static_cast<double>(c.n) / static_cast<double>(t.labelled));
    if (!top || c.n > top->n || (c.n == top->n && c.confidence > top->confidence)) {
      top = &c;
      t.label = label;
    }
  }
  t.share = static_cast<double>(top->n) / static_cast<double>(t.labelled);
  t.robust = t.runs >= 2 && t.labelled == t.runs && top->n == t.runs;

  // The runner-up: the second most frequent class, else the majority's most frequent runner-up.
  std::map<std::string, std::size_t> others, runner_ups;
  for (const auto& [label, c] : classes) {
    if (label != *t.label) others[label] = c.n;
  }
  for (const adaptive::Labelled& r : finished) {
    if (r.label == t.label && r.runner_up) ++runner_ups[*r.runner_up];
  }
  const auto runner_up = others.empty() ? most_frequent(runner_ups) : most_frequent(others);
  t.as_run = {point, t.label, t.share * top->confidence / static_cast<double>(top->n), runner_up};
  return t;
}

std::optional<Spread> spread(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  Spread s;
  s.n = values.size();
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(s.n);
  if (s.n >= 2) {
    double sq = 0;
    for (double v : values) sq += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(sq / static_cast<double>(s.n - 1));
  }
  return s;
}

}  // namespace compaction::server
