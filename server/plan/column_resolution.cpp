#include "plan/column_resolution.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace compaction::server::adaptive {

std::vector<ColumnResolution> column_resolution(const LevelsSpec& spec,
                                                const std::vector<NodeLabel>& nodes) {
  const double finest_R = finest_steps(spec.box).R;
  std::map<long long, std::vector<const NodeLabel*>> columns;  // lattice column -> its points
  for (const NodeLabel& n : nodes) {
    if (const auto at = lattice_node(spec.box, n.point)) columns[at->i].push_back(&n);
  }
  std::vector<ColumnResolution> out;
  for (auto& [i, points] : columns) {
    std::sort(points.begin(), points.end(),
              [](const NodeLabel* a, const NodeLabel* b) { return a->point.R < b->point.R; });
    ColumnResolution c;
    c.S = points.front()->point.S;
    c.points = points.size();
    for (std::size_t k = 0; k < points.size(); ++k) {
      c.finest_level = std::max(c.finest_level, points[k]->level);
      if (k == 0 || points[k]->tally.label == points[k - 1]->tally.label) continue;
      ++c.boundaries;
      const double gap = std::log10(points[k]->point.R / points[k - 1]->point.R);
      c.bracket_decades = std::max(c.bracket_decades.value_or(0.0), gap);
      if (gap > finest_R * (1 + kStepSlack)) c.resolved = false;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace compaction::server::adaptive
