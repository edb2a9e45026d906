// How finely an adaptive sweep has found its boundaries in each S column of its lattice (GET
// /api/v1/sweeps/{id}/plan, "columns"; the dashboard's plan page): along R at one S, two
// neighbouring points whose labels differ (or a label beside an unknown: a failed or
// unclassified point) bracket a boundary, and the gap between them in decades is how finely
// that boundary is known there. A column is resolved when every bracket is within the sweep's
// finest R step. A pure function of the points' labels (levels_plan.hpp, node_labels): the
// label of each point at its finest finished level.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "plan/levels_plan.hpp"

namespace compaction::server::adaptive {

struct ColumnResolution {
  double S = 0;
  std::size_t points = 0;      // points of the lattice at this S with a finished level
  std::size_t boundaries = 0;  // neighbours along R whose labels differ
  // The widest R gap across a boundary, in decades (none without a boundary); resolved when no
  // gap is wider than the finest R step.
  std::optional<double> bracket_decades;
  bool resolved = true;
  int finest_level = 0;  // the finest level finished at any point of the column
};

// One entry per S of the lattice that holds a point, in increasing S. Points off the lattice
// (given points of another sweep) are not read.
std::vector<ColumnResolution> column_resolution(const LevelsSpec& spec,
                                                const std::vector<NodeLabel>& nodes);

}  // namespace compaction::server::adaptive
