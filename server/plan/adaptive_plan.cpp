#include "plan/adaptive_plan.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "plan/round_significant.hpp"

// The planning of adaptive_plan.hpp: the lattice, the quadtree walk and the ranking. The
// request's spec is read in adaptive_spec.cpp.
namespace compaction::server::adaptive {

namespace {

// The distance (in finest steps) within which a given point counts as a node of the lattice:
// far above the rounding of values to 12 significant digits, far below a step.
constexpr double kSnap = 1e-6;

double decades(const AxisRange& a) { return std::log10(a.max) - std::log10(a.min); }

// Halvings of `step` that keep it >= resolution.
int halvings(double step, double resolution) {
  int n = 0;
  while (step / 2 >= resolution * (1 - kStepSlack)) {
    step /= 2;
    ++n;
  }
  return n;
}

// A node of the finest lattice: i along log S, j along log R, from the box's lower corner.
using Node = std::pair<long long, long long>;

// The finest lattice of a spec: the initial grid's nodes are every width-th node.
struct Lattice {
  long long width_S = 1, width_R = 1;  // an initial cell in finest steps (powers of two)
  long long nodes_S = 0, nodes_R = 0;  // finest steps across the box
  double step_S = 0, step_R = 0;       // finest step in decades
  double log_S0 = 0, log_R0 = 0;

  explicit Lattice(const AdaptiveSpec& spec) {
    const double initial_S = decades(spec.S) / (spec.initial_S - 1);
    const double initial_R = decades(spec.R) / (spec.initial_R - 1);
    width_S = 1LL << halvings(initial_S, spec.resolution_decades);
    width_R = 1LL << halvings(initial_R, spec.resolution_decades);
    nodes_S = (spec.initial_S - 1) * width_S;
    nodes_R = (spec.initial_R - 1) * width_R;
    step_S = initial_S / static_cast<double>(width_S);
    step_R = initial_R / static_cast<double>(width_R);
    log_S0 = std::log10(spec.S.min);
    log_R0 = std::log10(spec.R.min);
  }
};

// expand_axis's log grid: min (max/min)^(k/n), 12 significant digits, the ends as written. For an
// initial node k = m width the fraction is the same double as m / (initial - 1).
double axis_value(const AxisRange& a, long long k, long long n) {
  if (k == 0) return a.min;
  if (k == n) return a.max;
  const double t = static_cast<double>(k) / static_cast<double>(n);
  return round_significant(a.min * std::pow(a.max / a.min, t));
}

Point point_at(const AdaptiveSpec& spec, const Lattice& L, Node n) {
  return {axis_value(spec.S, n.first, L.nodes_S), axis_value(spec.R, n.second, L.nodes_R)};
}

// The node a point sits on, if it sits on one inside the box.
std::optional<Node> node_of(const Lattice& L, Point p) {
  if (!(p.S > 0) || !(p.R > 0)) return std::nullopt;
  const double i = (std::log10(p.S) - L.log_S0) / L.step_S;
  const double j = (std::log10(p.R) - L.log_R0) / L.step_R;
  const double ri = std::round(i), rj = std::round(j);
  if (std::abs(i - ri) > kSnap || std::abs(j - rj) > kSnap) return std::nullopt;
  if (ri < 0 || rj < 0 || ri > static_cast<double>(L.nodes_S) || rj > static_cast<double>(L.nodes_R)) {
    return std::nullopt;
  }
  return Node{static_cast<long long>(ri), static_cast<long long>(rj)};
}

struct Known {
  std::optional<std::string> label;
  double confidence = 0;
};

// The better of two results at one node (a duplicate in done): a label over none, then the
// higher confidence, then the smaller label; so the input's order never matters.
bool better(const Known& a, const Known& b) {
  if (a.label.has_value() != b.label.has_value()) return a.label.has_value();
  if (!a.label) return false;
  if (a.confidence != b.confidence) return a.confidence > b.confidence;
  return *a.label < *b.label;
}

// How unsure a labelled result is: 0 from kConfidentFrom up, 1 at confidence 0.
double uncertainty(const Known& k) {
  return std::clamp(1.0 - k.confidence / kConfidentFrom, 0.0, 1.0);
}

// What the planner knows: results and queued points on the lattice (with the results also
// ordered by row, to find the points on a cell's edges), and the logs of points off it.
struct State {
  const AdaptiveSpec& spec;
  Lattice L;
  std::map<Node, Known> done;           // by column: (i, j)
  std::set<Node> done_by_row;           // (j, i)
  std::set<Node> pending;
  std::vector<std::pair<double, double>> elsewhere;  // (log10 S, log10 R) of off-lattice points

  State(const AdaptiveSpec& s, const std::vector<Labelled>& results, const std::vector<Point>& queued)
      : spec(s), L(s) {
    for (const Labelled& r : results) {
      const Known k{r.label, r.confidence};
      if (const auto n = node_of(L, r.point)) {
        auto [it, inserted] = done.emplace(*n, k);
        if (!inserted && better(k, it->second)) it->second = k;
        done_by_row.insert({n->second, n->first});
      } else {
        elsewhere.push_back({std::log10(r.point.S), std::log10(r.point.R)});
      }
    }
    for (const Point& p : queued) {
      if (const auto n = node_of(L, p)) {
        if (!done.count(*n)) pending.insert(*n);
      } else {
        elsewhere.push_back({std::log10(p.S), std::log10(p.R)});
      }
    }
  }

  bool known(Node n) const { return done.count(n) || pending.count(n); }

  // Whether an off-lattice point lies closer than the resolution on both axes.
  bool crowded(Node n) const {
    const double x = L.log_S0 + static_cast<double>(n.first) * L.step_S;
    const double y = L.log_R0 + static_cast<double>(n.second) * L.step_R;
    const double r = spec.resolution_decades * (1 - kStepSlack);
    return std::any_of(elsewhere.begin(), elsewhere.end(), [&](const auto& e) {
      return std::abs(e.first - x) < r && std::abs(e.second - y) < r;
    });
  }
};

// A cell of the quadtree: lower corner and sides in finest steps.
struct Cell {
  long long i0, j0, wi, wj;
};

struct Disagreement {
  double weight = 0;
  bool labels = false;  // two labels, or a label and an unknown (what resolved() looks at)
};

// The disagreement of the results on a cell's boundary: its corners and the points its
// neighbours' splits put on its edges.
Disagreement disagreement(const State& st, const Cell& c) {
  std::set<std::string> labels;
  bool unknown = false;
  double unsure = 0;
  auto take = [&](const Known& k) {
    if (!k.label) {
      unknown = true;
      return;
    }
    labels.insert(*k.label);
    unsure = std::max(unsure, uncertainty(k));
  };
  const long long i1 = c.i0 + c.wi, j1 = c.j0 + c.wj;
  for (long long i : {c.i0, i1}) {  // the two vertical edges, corners included
    for (auto it = st.done.lower_bound({i, c.j0}); it != st.done.end() && it->first.first == i &&
                                                   it->first.second <= j1; ++it) {
      take(it->second);
    }
  }
  for (long long j : {c.j0, j1}) {  // the two horizontal edges, without the corners
    for (auto it = st.done_by_row.upper_bound({j, c.i0});
         it != st.done_by_row.end() && it->first == j && it->second < i1; ++it) {
      take(st.done.at({it->second, it->first}));
    }
  }
  Disagreement d;
  if (labels.size() >= 2) {
    d.weight = kWeightLabelsDiffer;
    d.labels = true;
  } else if (labels.size() == 1) {
    d.weight = kWeightLowConfidence * unsure;
    if (unknown) {
      d.weight = std::max(d.weight, kWeightUnknown);
      d.labels = true;
    }
  }
  return d;
}

// Walks the quadtree as the results define it: a cell whose four corners are done and whose
// boundary disagrees is split; the nodes of the split that nobody has run or queued are
// candidates worth weight x size; its children are walked when their corners are done.
struct Walk {
  const State& st;
  std::map<Node, double> value;  // candidates, the best value asking for each
  bool unresolved = false;

  void visit(const Cell& c) {
    const long long i1 = c.i0 + c.wi, j1 = c.j0 + c.wj;
    for (Node n : {Node{c.i0, c.j0}, Node{i1, c.j0}, Node{c.i0, j1}, Node{i1, j1}}) {
      if (!st.done.count(n)) return;  // queued or not yet asked for: wait
    }
    const bool split_S = c.wi > 1, split_R = c.wj > 1;
    if (!split_S && !split_R) return;  // the finest cell: the boundary is located
    const Disagreement d = disagreement(st, c);
    if (d.weight <= 0) return;

    const double size = std::max(static_cast<double>(c.wi) * st.L.step_S,
                                 static_cast<double>(c.wj) * st.L.step_R);
    const long long hi = split_S ? c.wi / 2 : c.wi, hj = split_R ? c.wj / 2 : c.wj;
    bool children_done = true;
    for (long long a = 0; a * hi <= c.wi; ++a) {
      for (long long b = 0; b * hj <= c.wj; ++b) {
        const Node n{c.i0 + a * hi, c.j0 + b * hj};
        if (st.done.count(n)) continue;
        children_done = false;
        if (st.pending.count(n) || st.crowded(n)) continue;
        double& v = value[n];
        v = std::max(v, d.weight * size);
      }
    }
    if (d.labels && !children_done) unresolved = true;
    for (long long a = 0; a * hi < c.wi; ++a) {
      for (long long b = 0; b * hj < c.wj; ++b) visit({c.i0 + a * hi, c.j0 + b * hj, hi, hj});
    }
  }
};

// Walks every initial cell; missing initial nodes are candidates before any cell's.
Walk walk(const State& st) {
  Walk w{st, {}, false};
  const Lattice& L = st.L;
  const double initial_value = 2 * std::max(static_cast<double>(L.nodes_S) * L.step_S,
                                            static_cast<double>(L.nodes_R) * L.step_R);
  for (long long i = 0; i <= L.nodes_S; i += L.width_S) {
    for (long long j = 0; j <= L.nodes_R; j += L.width_R) {
      const Node n{i, j};
      if (st.known(n)) continue;
      w.unresolved = true;
      if (!st.crowded(n)) w.value[n] = initial_value;
    }
  }
  for (long long i = 0; i < L.nodes_S; i += L.width_S) {
    for (long long j = 0; j < L.nodes_R; j += L.width_R) w.visit({i, j, L.width_S, L.width_R});
  }
  return w;
}

}  // namespace

Steps finest_steps(const AdaptiveSpec& spec) {
  const Lattice L(spec);
  return {L.step_S, L.step_R};
}

std::vector<Point> initial_points(const AdaptiveSpec& spec) {
  const Lattice L(spec);
  std::vector<Point> out;
  for (long long j = 0; j <= L.nodes_R; j += L.width_R) {
    for (long long i = 0; i <= L.nodes_S; i += L.width_S) out.push_back(point_at(spec, L, {i, j}));
  }
  return out;
}

std::vector<Proposal> ranked_candidates(const AdaptiveSpec& spec, const std::vector<Labelled>& done,
                                        const std::vector<Point>& pending) {
  const State st(spec, done, pending);
  const Walk w = walk(st);
  std::vector<std::pair<Node, double>> ranked(w.value.begin(), w.value.end());
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    if (a.second != b.second) return a.second > b.second;               // most valuable
    if (a.first.first != b.first.first) return a.first.first > b.first.first;  // larger S
    return a.first.second < b.first.second;                             // then smaller R
  });
  std::vector<Proposal> out;
  for (const auto& [node, value] : ranked) out.push_back({point_at(spec, st.L, node), value});
  return out;
}

std::vector<Point> next_points(const AdaptiveSpec& spec, const std::vector<Labelled>& done,
                               const std::vector<Point>& pending, std::size_t how_many) {
  const std::size_t used = done.size() + pending.size();
  const std::size_t left = spec.budget > used ? spec.budget - used : 0;
  const std::size_t n = std::min(how_many, left);
  if (n == 0) return {};
  std::vector<Point> out;
  for (const Proposal& p : ranked_candidates(spec, done, pending)) {
    if (out.size() == n) break;
    out.push_back(p.point);
  }
  return out;
}

bool resolved(const AdaptiveSpec& spec, const std::vector<Labelled>& done) {
  const State st(spec, done, {});
  return !walk(st).unresolved;
}

LatticeShape lattice_shape(const AdaptiveSpec& spec) {
  const Lattice L(spec);
  return {L.width_S, L.width_R, L.nodes_S, L.nodes_R};
}

std::optional<LatticeNode> lattice_node(const AdaptiveSpec& spec, Point p) {
  const auto n = node_of(Lattice(spec), p);
  if (!n) return std::nullopt;
  return LatticeNode{n->first, n->second};
}

std::optional<Point> lattice_point(const AdaptiveSpec& spec, LatticeNode n) {
  const Lattice L(spec);
  if (n.i < 0 || n.j < 0 || n.i > L.nodes_S || n.j > L.nodes_R) return std::nullopt;
  return point_at(spec, L, {n.i, n.j});
}

}  // namespace compaction::server::adaptive
