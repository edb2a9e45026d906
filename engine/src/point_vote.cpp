#include "compaction/point_vote.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "compaction/params_json.hpp"

namespace compaction {

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

// The runner-up: the second most frequent class, else the majority's most frequent runner-up.
std::optional<std::string> runner_up_of(const std::vector<Vote>& finished,
                                        const std::map<std::string, ClassCount>& classes,
                                        const std::string& label) {
  std::map<std::string, std::size_t> others, runner_ups;
  for (const auto& [other, c] : classes) {
    if (other != label) others[other] = c.n;
  }
  for (const Vote& v : finished) {
    if (v.label == label && v.runner_up) ++runner_ups[*v.runner_up];
  }
  return others.empty() ? most_frequent(runner_ups) : most_frequent(others);
}

}  // namespace

PointVote vote(const std::vector<Vote>& finished, std::size_t runs) {
  PointVote p;
  p.runs = std::max(runs, finished.size());
  std::map<std::string, ClassCount> classes;  // ordered: class order
  for (const Vote& v : finished) {
    if (!v.label) continue;
    ++p.labelled;
    ClassCount& c = classes[*v.label];
    ++c.n;
    c.confidence += v.confidence;
  }
  if (p.labelled == 0) return p;

  const ClassCount* top = nullptr;
  for (const auto& [label, c] : classes) {
    p.probabilities.emplace_back(label, static_cast<double>(c.n) / static_cast<double>(p.labelled));
    if (!top || c.n > top->n || (c.n == top->n && c.confidence > top->confidence)) {
      top = &c;
      p.label = label;
    }
  }
  p.share = static_cast<double>(top->n) / static_cast<double>(p.labelled);
  p.robust = p.runs >= 2 && p.labelled == p.runs && top->n == p.runs;
  p.confidence = p.share * top->confidence / static_cast<double>(top->n);
  p.runner_up = runner_up_of(finished, classes, *p.label);
  return p;
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

std::optional<std::string> differs_beyond_seed(const SceneParams& a, const SceneParams& b) {
  nlohmann::json ja = to_json(a), jb = to_json(b);
  ja.erase("seed");
  jb.erase("seed");
  for (const auto& [key, value] : ja.items()) {
    if (!jb.contains(key) || jb[key] != value) return key;
  }
  for (const auto& [key, value] : jb.items()) {
    if (!ja.contains(key)) return key;
  }
  return std::nullopt;
}

}  // namespace compaction
