#include "plan/phase_regions.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace compaction::server::regions {

namespace {

// A labelled run as the vote reads it: its place in decades and its two classes as indices
// into the sorted list of every class named (no runner-up: -1).
struct Voter {
  double x = 0, y = 0;
  int label = 0, runner_up = -1;
  double confidence = 0;
  double share = 1;  // the run's share of its point's vote (Labelled::share)
};

struct Voters {
  std::vector<std::string> classes;  // sorted
  std::vector<Voter> list;           // sorted by x, then y, label, runner-up, confidence
};

Voters prepare(const std::vector<adaptive::Labelled>& runs) {
  Voters v;
  for (const auto& r : runs) {
    if (!r.label) continue;
    v.classes.push_back(*r.label);
    if (r.runner_up) v.classes.push_back(*r.runner_up);
  }
  std::sort(v.classes.begin(), v.classes.end());
  v.classes.erase(std::unique(v.classes.begin(), v.classes.end()), v.classes.end());
  const auto index = [&](const std::string& c) {
    return static_cast<int>(std::lower_bound(v.classes.begin(), v.classes.end(), c) -
                            v.classes.begin());
  };
  for (const auto& r : runs) {
    if (!r.label || !(r.point.S > 0) || !(r.point.R > 0)) continue;
    Voter w;
    w.x = std::log10(r.point.S);
    w.y = std::log10(r.point.R);
    w.label = index(*r.label);
    // A runner-up equal to the label adds nothing a second time: the whole vote is the label's.
    w.runner_up = r.runner_up && *r.runner_up != *r.label ? index(*r.runner_up) : -1;
    w.confidence = std::clamp(r.confidence, 0.0, 1.0);
    w.share = std::clamp(r.share, 0.0, 1.0);
    v.list.push_back(w);
  }
  // A fixed order of summation: the same bits whatever order the runs came in.
  std::sort(v.list.begin(), v.list.end(), [](const Voter& a, const Voter& b) {
    return std::tie(a.x, a.y, a.label, a.runner_up, a.confidence, a.share) <
           std::tie(b.x, b.y, b.label, b.runner_up, b.confidence, b.share);
  });
  return v;
}

constexpr double kCutoff = kCutoffSigmas * kBandwidthDecades;
constexpr double kInv2h2 = 1.0 / (2 * kBandwidthDecades * kBandwidthDecades);

// The kernel's factor along one axis at distance d: exp(-d^2 / (2 h^2)). A run's weight is the
// product of its x and y factors, each computed once per column and once per row of the grid
// (an exponential per run and cell was most of the answer's time).
double factor(double d) { return std::exp(-d * d * kInv2h2); }

// The cell rule at (x, y) over the voters [first, last) (those within the cutoff in x; the
// others are skipped by distance), with their x factors ex[k - first] at x and their y factors
// ey[k] at y. votes: scratch of classes.size() entries.
Cell vote(const Voters& v, std::size_t first, std::size_t last, double x, double y,
          const double* ex, const double* ey, std::vector<double>& votes) {
  std::fill(votes.begin(), votes.end(), 0.0);
  double evidence = 0;
  for (std::size_t k = first; k < last; ++k) {
    const Voter& w = v.list[k];
    const double dx = w.x - x, dy = w.y - y;
    const double d2 = dx * dx + dy * dy;
    if (d2 > kCutoff * kCutoff) continue;
    const double weight = ex[k - first] * ey[k] * w.share;
    evidence += weight;
    votes[w.label] += weight * (1 + w.confidence) / 2;
    if (w.runner_up >= 0) votes[w.runner_up] += weight * (1 - w.confidence) / 2;
  }
  Cell c;
  if (!(evidence > 0)) return c;
  int best = 0;
  for (int k = 1; k < static_cast<int>(votes.size()); ++k) {
    if (votes[k] > votes[best]) best = k;
  }
  double second = 0;
  for (int k = 0; k < static_cast<int>(votes.size()); ++k) {
    if (k != best) second = std::max(second, votes[k]);
  }
  const double margin = (votes[best] - second) / evidence;
  const double reach = 1 - std::exp(-evidence / kEvidenceScale);
  c.cls = v.classes[best];
  c.uncertainty = std::clamp(1 - margin * reach, 0.0, 1.0);
  return c;
}

// The voters whose x lies within the cutoff of x: [first, last).
std::pair<std::size_t, std::size_t> column(const Voters& v, double x) {
  const auto lo = std::lower_bound(v.list.begin(), v.list.end(), x - kCutoff,
                                   [](const Voter& w, double t) { return w.x < t; });
  const auto hi = std::upper_bound(v.list.begin(), v.list.end(), x + kCutoff,
                                   [](double t, const Voter& w) { return t < w.x; });
  return {static_cast<std::size_t>(lo - v.list.begin()),
          static_cast<std::size_t>(hi - v.list.begin())};
}

void widen(double& lo, double& hi) {
  if (hi - lo < kMinSpanDecades) {
    const double c = (lo + hi) / 2;
    lo = c - kMinSpanDecades / 2;
    hi = c + kMinSpanDecades / 2;
  }
  lo -= kPadDecades;
  hi += kPadDecades;
}

}  // namespace

std::optional<Box> box_of(const std::vector<adaptive::Point>& points) {
  std::optional<Box> b;
  for (const auto& p : points) {
    if (!(p.S > 0) || !(p.R > 0)) continue;
    const double x = std::log10(p.S), y = std::log10(p.R);
    if (!b) {
      b = Box{x, x, y, y};
      continue;
    }
    b->log_S_min = std::min(b->log_S_min, x);
    b->log_S_max = std::max(b->log_S_max, x);
    b->log_R_min = std::min(b->log_R_min, y);
    b->log_R_max = std::max(b->log_R_max, y);
  }
  if (b) {
    widen(b->log_S_min, b->log_S_max);
    widen(b->log_R_min, b->log_R_max);
  }
  return b;
}

double Regions::log_S(int i) const {
  return box.log_S_min + (i + 0.5) * (box.log_S_max - box.log_S_min) / grid;
}

double Regions::log_R(int j) const {
  return box.log_R_min + (j + 0.5) * (box.log_R_max - box.log_R_min) / grid;
}

Regions predict(const std::vector<adaptive::Labelled>& runs, const Box& box, int grid) {
  Regions out;
  out.box = box;
  out.grid = std::max(grid, 1);
  const Voters v = prepare(runs);
  out.runs = v.list.size();
  out.cells.resize(static_cast<std::size_t>(out.grid) * out.grid);
  const std::size_t n = v.list.size();
  // The y factor of every run at every row (grid x runs: 20 MB for 256 rows and 10 000 runs).
  std::vector<double> ey(static_cast<std::size_t>(out.grid) * n);
  for (int j = 0; j < out.grid; ++j) {
    for (std::size_t k = 0; k < n; ++k) ey[j * n + k] = factor(v.list[k].y - out.log_R(j));
  }
  std::vector<double> votes(v.classes.size()), ex;
  for (int i = 0; i < out.grid; ++i) {
    const double x = out.log_S(i);
    const auto [first, last] = column(v, x);
    ex.resize(last - first);
    for (std::size_t k = first; k < last; ++k) ex[k - first] = factor(v.list[k].x - x);
    for (int j = 0; j < out.grid; ++j) {
      out.cells[static_cast<std::size_t>(j) * out.grid + i] =
          vote(v, first, last, x, out.log_R(j), ex.data(), ey.data() + j * n, votes);
    }
  }
  return out;
}

Cell predict_at(const std::vector<adaptive::Labelled>& runs, double log_S, double log_R) {
  const Voters v = prepare(runs);
  std::vector<double> votes(v.classes.size()), ex, ey;
  const auto [first, last] = column(v, log_S);
  for (std::size_t k = first; k < last; ++k) ex.push_back(factor(v.list[k].x - log_S));
  for (const Voter& w : v.list) ey.push_back(factor(w.y - log_R));
  return vote(v, first, last, log_S, log_R, ex.data(), ey.data(), votes);
}

}  // namespace compaction::server::regions
