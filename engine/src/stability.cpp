#include "stability.hpp"

#include <cmath>
#include <cstdio>

namespace compaction {

namespace {
std::string format(const char* fmt, double a, double b) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
}  // namespace

std::string check_step(const State& s) {
  const StepMeasure& m = s.measure;
  const Grid& g = s.grid;
  if (m.bad_jacobian) return "deformation gradient inverted or not finite (J <= 0 or NaN)";
  const double c = s.setup.c_p;
  if (!(m.max_v2 < c * c)) {
    // A particle as fast as the elastic waves is far beyond any speed this loading can give.
    return format("particle speed %.3g m/s reached the P-wave speed %.3g m/s (or is NaN)",
                  std::sqrt(m.max_v2), c);
  }
  // A stencil needs its nodes inside the grid: stop 1.4 cells before its edge.
  const double y_lo = (1.4 - g.gy) * g.dx, y_hi = (g.ny - g.gy - 2.6) * g.dx;
  if (!(m.y_min >= y_lo && m.y_max <= y_hi)) {
    return format("a particle left the domain vertically (y from %.4g to %.4g m)", m.y_min,
                  m.y_max);
  }
  if (!g.periodic_x) {
    const double x_lo = (1.4 - g.gx) * g.dx, x_hi = (g.nx - g.gx - 2.6) * g.dx;
    if (!(m.x_min >= x_lo && m.x_max <= x_hi)) {
      return format("a particle left the domain sideways (x from %.4g to %.4g m)", m.x_min,
                    m.x_max);
    }
  }
  return {};
}

std::string check_frame(const State& s, const Frame& f) {
  if (!std::isfinite(f.sigma_top) || !std::isfinite(f.sigma_bottom) ||
      !std::isfinite(f.kinetic_energy)) {
    return "plate stress or kinetic energy not finite";
  }
  // Energy: the plates are the only source, so kinetic energy above the work they did means
  // the scheme creates energy. A floor of 1 % of the kinetic energy of the whole specimen
  // moving at V covers the first frames, when both are tiny.
  const Particles& P = s.particles;
  const double floor = 0.01 * 0.5 * P.mass * P.n * s.setup.V * s.setup.V;
  if (f.kinetic_energy > 2.0 * f.plate_work + floor) {
    return format("kinetic energy %.4g J/m exceeds twice the work of the plates %.4g J/m",
                  f.kinetic_energy, f.plate_work);
  }
  return {};
}

}  // namespace compaction
