// Time step from the CFL condition on the P-wave speed plus the fastest particle.
#include <cmath>

#include "stages.hpp"

namespace compaction {

double stable_dt(const State& s, double cfl) {
  const double vmax = std::sqrt(s.measure.max_v2);
  return cfl * s.grid.dx / (s.setup.c_p + (std::isfinite(vmax) ? vmax : 0.0));
}

}  // namespace compaction
