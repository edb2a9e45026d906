// The box of issue 47's trusted map as a levels planner's spec (plan/levels_plan.hpp), for the
// planner's tests: S 3e-3..3e-2, R 1e-5..1e-2, initial 3 x 4, an eighth of a decade: a lattice
// of 9 x 25 nodes.
#pragma once

#include <cstddef>

#include "plan/levels_plan.hpp"

namespace compaction::server::adaptive {

inline LevelsSpec trusted_spec(int levels, std::size_t replicates, std::size_t budget) {
  LevelsSpec s;
  s.box.S = {3e-3, 3e-2};
  s.box.R = {1e-5, 1e-2};
  s.box.initial_S = 3;
  s.box.initial_R = 4;
  s.box.resolution_decades = 0.125;
  s.box.budget = budget;
  s.box.in_flight = 8;
  s.levels = levels;
  s.replicates = replicates;
  return s;
}

}  // namespace compaction::server::adaptive
