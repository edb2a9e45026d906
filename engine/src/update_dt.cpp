// Time step from the CFL condition on the P-wave speed plus the fastest particle, in 2D and in
// 3D (the rule itself: compaction::cfl_time_step).
#include <cmath>

#include "stages.hpp"
#include "stages_3d.hpp"

namespace compaction {

double stable_dt(const State& s, double cfl) {
  return cfl_time_step(cfl, s.grid.dx, s.setup.c_p, std::sqrt(s.measure.max_v2));
}

double stable_dt_3d(const State3D& s, double cfl) {
  return cfl_time_step(cfl, s.grid.dx, s.setup.c_p, std::sqrt(s.measure.max_v2));
}

}  // namespace compaction
