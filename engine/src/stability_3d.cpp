#include "stability_3d.hpp"

#include <cmath>
#include <cstdio>

namespace compaction {

std::string check_step_3d(const State3D& s) {
  const StepMeasure& m = s.measure;
  const Grid3D& g = s.grid;
  char buf[256];
  if (m.bad_jacobian) return "deformation gradient inverted or not finite (J <= 0 or NaN)";
  const double c = s.setup.c_p;
  if (!(m.max_v2 < c * c)) {
    std::snprintf(buf, sizeof buf, "particle speed %.3g m/s reached the P-wave speed %.3g m/s (or is NaN)",
                  std::sqrt(m.max_v2), c);
    return buf;
  }
  const double y_lo = (1.4 - g.gy) * g.dx, y_hi = (g.ny - g.gy - 2.6) * g.dx;
  if (!(m.y_min >= y_lo && m.y_max <= y_hi)) {
    std::snprintf(buf, sizeof buf, "a particle left the domain vertically (y from %.4g to %.4g m)",
                  m.y_min, m.y_max);
    return buf;
  }
  return {};
}

std::string check_frame_3d(const State3D& s, const Frame& f) {
  if (!std::isfinite(f.sigma_top) || !std::isfinite(f.sigma_bottom) ||
      !std::isfinite(f.kinetic_energy)) {
    return "plate stress or kinetic energy not finite";
  }
  const Particles3D& P = s.particles;
  const double floor = 0.01 * 0.5 * P.mass * P.n * s.setup.V * s.setup.V;
  if (f.kinetic_energy > 2.0 * f.plate_work + floor) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "kinetic energy %.4g J exceeds twice the work of the plates %.4g J",
                  f.kinetic_energy, f.plate_work);
    return buf;
  }
  return {};
}

}  // namespace compaction
