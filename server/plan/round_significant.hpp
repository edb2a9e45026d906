// Grid values to 12 significant digits, so that a value like 10^(-2) computed on a log grid hits
// the same double as the literal 0.01 does (identical parameters must compare equal for reuse).
// The planner's grids (planner.cpp, expand_axis) and the adaptive planner's lattice
// (adaptive_plan.cpp) both round through here.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace compaction::server {

inline double round_significant(double v) {
  if (!std::isfinite(v) || v == 0.0) return v;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return std::strtod(buf, nullptr);
}

}  // namespace compaction::server
