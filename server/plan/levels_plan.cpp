#include "plan/levels_plan.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>
#include <utility>

namespace compaction::server::adaptive {

namespace {

// A point's runs at one level.
struct AtLevel {
  std::vector<Labelled> finished;
  std::size_t pending = 0;
  std::size_t runs() const { return finished.size() + pending; }
};

// A point's runs at every level, and what they say.
struct PointRuns {
  Point point;
  std::map<int, AtLevel> levels;

  std::size_t runs(int level) const {
    const auto it = levels.find(level);
    return it == levels.end() ? 0 : it->second.runs();
  }
  // The highest level with a run, and whether all its runs have finished.
  int top() const { return levels.empty() ? -1 : levels.rbegin()->first; }
  bool settled() const { return !levels.empty() && levels.rbegin()->second.pending == 0; }
  Tally tally_at(int level) const {
    const AtLevel& a = levels.at(level);
    return tally(point, a.finished, a.runs());
  }
  // The label of a level whose runs have all finished (none: unknown, a failed run's).
  bool complete(int level) const {
    const auto it = levels.find(level);
    return it != levels.end() && it->second.pending == 0 && !it->second.finished.empty();
  }
};

using Key = std::pair<double, double>;  // (S, R): runs of one point at any level

struct Board {
  const LevelsSpec& spec;
  LatticeShape shape;
  double step = 0;  // the finest step's longer side in decades: the trust actions' size
  std::map<Key, PointRuns> points;
  std::map<LatticeNode, const PointRuns*> nodes;

  Board(const LevelsSpec& s, const std::vector<LevelRun>& done, const std::vector<LevelQueued>& pending)
      : spec(s), shape(lattice_shape(s.box)) {
    const Steps st = finest_steps(s.box);
    step = std::max(st.S, st.R);
    for (const LevelRun& r : done) {
      PointRuns& p = points[{r.point.S, r.point.R}];
      p.point = r.point;
      p.levels[r.level].finished.push_back({r.point, r.label, r.confidence, r.runner_up});
    }
    for (const LevelQueued& q : pending) {
      PointRuns& p = points[{q.point.S, q.point.R}];
      p.point = q.point;
      ++p.levels[q.level].pending;
    }
    for (const auto& [key, p] : points) {
      if (const auto n = lattice_node(s.box, p.point)) nodes[*n] = &p;
    }
  }

  const PointRuns* at(LatticeNode n) const {
    const auto it = nodes.find(n);
    return it == nodes.end() ? nullptr : it->second;
  }
};

// Actions by point and level, the most valuable asking for each kept.
struct Actions {
  const Board& board;
  const RunCost& cost;
  std::map<std::tuple<double, double, int>, LevelAction> by_run;

  void add(Point p, int level, double value, const char* why) {
    const auto key = std::make_tuple(p.S, p.R, level);
    const auto it = by_run.find(key);
    if (it != by_run.end() && it->second.value >= value) return;
    const auto known = board.points.find({p.S, p.R});
    const std::size_t runs = known == board.points.end() ? 0 : known->second.runs(level);
    by_run[key] = {p, level, runs, value, cost(p, level), why};
  }
  void add_at(LatticeNode n, int level, double value, const char* why) {
    if (const auto p = lattice_point(board.spec.box, n)) add(*p, level, value, why);
  }
};

// The level-0 map as adaptive_plan reads it: each point by the majority of its level-0 runs,
// pending while one of them is.
void map_coarsest(const Board& b, std::vector<Labelled>& done, std::vector<Point>& pending) {
  for (const auto& [key, p] : b.points) {
    const auto it = p.levels.find(0);
    if (it == p.levels.end()) continue;
    if (it->second.pending > 0) {
      pending.push_back(p.point);
    } else {
      done.push_back(p.tally_at(0).as_run);
    }
  }
}

// Walks the quadtree by each corner's label at its highest level (best label), with the
// coarsest level's splits left to adaptive_plan: a cell whose corners disagree across levels
// has its lower corners run at the higher level (step 4); one whose corners disagree at one
// level above the coarsest is split at that level; a finest cell whose corners disagree at one
// level puts them on that level's boundary.
struct TrustWalk {
  const Board& b;
  Actions& actions;
  std::map<int, std::set<LatticeNode>> boundary;  // by level
  bool waiting = false;                          // a cell waits for a pending run

  void visit(long long i0, long long j0, long long wi, long long wj) {
    const LatticeNode corners[4] = {{i0, j0}, {i0 + wi, j0}, {i0, j0 + wj}, {i0 + wi, j0 + wj}};
    std::set<std::string> labels;
    bool unknown = false;
    int lo = 1 << 30, hi = -1;
    for (const LatticeNode& n : corners) {
      const PointRuns* p = b.at(n);
      if (!p) return;  // not run yet: the coarsest level's walk decides
      if (!p->settled()) {
        waiting = true;
        return;
      }
      const int level = p->top();
      lo = std::min(lo, level);
      hi = std::max(hi, level);
      if (const auto label = p->tally_at(level).label) {
        labels.insert(*label);
      } else {
        unknown = true;
      }
    }
    const long long half_i = wi > 1 ? wi / 2 : wi, half_j = wj > 1 ? wj / 2 : wj;
    // A cell that was split (every point of its split has a run, at any level) is read by its
    // children: they see the boundary closer than its corners do. A point on its edge alone
    // may come from a neighbour's split.
    bool split = wi > 1 || wj > 1;
    for (long long a = 0; a * half_i <= wi && split; ++a) {
      for (long long c = 0; c * half_j <= wj && split; ++c) {
        if (!b.at({i0 + a * half_i, j0 + c * half_j})) split = false;
      }
    }
    if (split) {
      for (long long a = 0; a * half_i < wi; ++a) {
        for (long long c = 0; c * half_j < wj; ++c) visit(i0 + a * half_i, j0 + c * half_j, half_i, half_j);
      }
      return;
    }
    const bool disagree = labels.size() >= 2 || (unknown && !labels.empty());
    if (!disagree) return;
    const double size = std::max(static_cast<double>(wi), static_cast<double>(wj)) * b.step;
    if (lo < hi) {
      for (const LatticeNode& n : corners) {
        if (b.at(n)->top() < hi) actions.add_at(n, hi, kWeightFollow * size, "follow");
      }
    } else if (wi == 1 && wj == 1) {
      for (const LatticeNode& n : corners) boundary[hi].insert(n);
    } else if (hi >= 1) {  // at the coarsest level adaptive_plan splits
      for (long long a = 0; a * half_i <= wi; ++a) {
        for (long long c = 0; c * half_j <= wj; ++c) {
          const LatticeNode n{i0 + a * half_i, j0 + c * half_j};
          const PointRuns* p = b.at(n);
          if (!p || p->runs(hi) == 0) actions.add_at(n, hi, kWeightFollow * size, "follow");
        }
      }
    }
  }
};

// Steps 2 and 3 for every point: replicates on a level's boundary and of unsure points, the
// next level where a boundary stays after its replicates or the replicates disagree.
void trust_points(const Board& b, const TrustWalk& w, Actions& actions) {
  const std::size_t n = b.spec.replicates;
  const int finest = b.spec.levels - 1;
  for (const auto& [node, p] : b.nodes) {
    if (!p->settled()) continue;
    const int level = p->top();
    const Tally t = p->tally_at(level);
    const bool on_boundary = w.boundary.count(level) && w.boundary.at(level).count(node);
    const std::size_t runs = p->runs(level);
    const bool split = t.labelled > 0 && t.share < 1.0;  // its replicates disagree
    if ((on_boundary || split) && runs < n) {
      actions.add(p->point, level, kWeightBoundaryReplicate * b.step, "replicate");
    } else if (level < finest && runs >= n && (on_boundary || split)) {
      actions.add(p->point, level + 1, kWeightLevelUp * b.step, "level");
    } else if (!on_boundary && runs < n && t.as_run.label && t.as_run.confidence < kConfidentFrom) {
      actions.add(p->point, level,
                  kWeightUnsureReplicate * (1.0 - t.as_run.confidence / kConfidentFrom) * b.step,
                  "unsure");
    }
  }
}

// Every action: the coarsest level's map first (in adaptive_plan's order), then the trust
// actions by level, value, cost and larger S.
std::vector<LevelAction> rank(const LevelsSpec& spec, const Board& b, const std::vector<LevelQueued>& pending,
                              const RunCost& cost, bool& resolved) {
  std::vector<Labelled> done0;
  std::vector<Point> pending0;
  map_coarsest(b, done0, pending0);
  std::vector<LevelAction> out;
  for (const Proposal& p : ranked_candidates(spec.box, done0, pending0)) {
    out.push_back({p.point, 0, 0, p.value, cost(p.point, 0), "map"});
  }
  Actions actions{b, cost, {}};
  TrustWalk w{b, actions, {}, false};
  for (long long i = 0; i < b.shape.nodes_S; i += b.shape.width_S) {
    for (long long j = 0; j < b.shape.nodes_R; j += b.shape.width_R) {
      w.visit(i, j, b.shape.width_S, b.shape.width_R);
    }
  }
  trust_points(b, w, actions);
  std::vector<LevelAction> trust;
  for (const auto& [key, a] : actions.by_run) {
    // Never a second action for a run already queued, nor beyond n replicates.
    const auto known = b.points.find({a.point.S, a.point.R});
    if (known != b.points.end() && known->second.levels.count(a.level) &&
        known->second.levels.at(a.level).pending > 0) {
      continue;
    }
    if (a.replicate >= spec.replicates) continue;
    trust.push_back(a);
  }
  std::sort(trust.begin(), trust.end(), [](const LevelAction& x, const LevelAction& y) {
    return std::make_tuple(x.level, -x.value, x.cpu_seconds, -x.point.S, x.point.R) <
           std::make_tuple(y.level, -y.value, y.cpu_seconds, -y.point.S, y.point.R);
  });
  resolved = pending.empty() && adaptive::resolved(spec.box, done0) &&
             std::none_of(trust.begin(), trust.end(),
                          [](const LevelAction& a) { return std::string(a.why) != "unsure"; });
  out.insert(out.end(), trust.begin(), trust.end());
  return out;
}

}  // namespace

std::vector<LevelAction> ranked_level_actions(const LevelsSpec& spec, const std::vector<LevelRun>& done,
                                              const std::vector<LevelQueued>& pending,
                                              const RunCost& cost) {
  const Board b(spec, done, pending);
  bool resolved = false;
  return rank(spec, b, pending, cost, resolved);
}

std::vector<LevelAction> next_level_actions(const LevelsSpec& spec, const std::vector<LevelRun>& done,
                                            const std::vector<LevelQueued>& pending,
                                            const RunCost& cost, std::size_t how_many) {
  const std::size_t used = done.size() + pending.size();
  std::size_t left = spec.box.budget > used ? spec.box.budget - used : 0;
  double cpu = 0;
  for (const LevelRun& r : done) cpu += cost(r.point, r.level);
  for (const LevelQueued& q : pending) cpu += cost(q.point, q.level);
  std::vector<LevelAction> out;
  for (const LevelAction& a : ranked_level_actions(spec, done, pending, cost)) {
    if (out.size() == how_many || left == 0) break;
    if (cpu + a.cpu_seconds > spec.budget_cpu_seconds) continue;  // a cheaper one may fit
    cpu += a.cpu_seconds;
    --left;
    out.push_back(a);
  }
  return out;
}

bool levels_resolved(const LevelsSpec& spec, const std::vector<LevelRun>& done, const RunCost& cost) {
  const Board b(spec, done, {});
  bool resolved = false;
  rank(spec, b, {}, cost, resolved);
  return resolved;
}

std::vector<NodeLabel> node_labels(const LevelsSpec& spec, const std::vector<LevelRun>& done) {
  const Board b(spec, done, {});
  std::vector<NodeLabel> out;
  for (const auto& [key, p] : b.points) {
    std::optional<int> best;
    std::set<std::string> seen;
    for (const auto& [level, at] : p.levels) {
      if (!p.complete(level)) continue;
      best = level;
      if (const auto label = p.tally_at(level).label) seen.insert(*label);
    }
    if (!best) continue;
    out.push_back({p.point, *best, p.tally_at(*best), seen.size() > 1});
  }
  return out;
}

}  // namespace compaction::server::adaptive
