#include "diagnostics_3d.hpp"

#include <algorithm>
#include <cmath>

namespace compaction {

FrameRecorder3D::FrameRecorder3D(const State3D& s)
    : row_rate_(s.grid.cells_y), row_vy_(s.grid.cells_y), row_count_(s.grid.cells_y) {}

void FrameRecorder3D::record(State3D& s, double eps_begin, double eps_end, RunResult& out) {
  const Setup3D& su = s.setup;
  Particles3D& P = s.particles;
  const double d_eps = eps_end - eps_begin;
  const double frame_time = d_eps * su.h0 / su.V;
  const double area = su.width * su.width;
  const int rows = static_cast<int>(row_rate_.size());
  std::fill(row_rate_.begin(), row_rate_.end(), 0.0);
  std::fill(row_vy_.begin(), row_vy_.end(), 0.0);
  std::fill(row_count_.begin(), row_count_.end(), 0);
  double kinetic = 0.0, max_v2 = 0.0;
  std::size_t plastic = 0;
  for (std::size_t k = 0; k < P.n; ++k) {
    const double v2 = P.vx[k] * P.vx[k] + P.vy[k] * P.vy[k] + P.vz[k] * P.vz[k];
    kinetic += v2;
    max_v2 = std::max(max_v2, v2);
    if (P.dep[k] > 0.0) ++plastic;
    const int row = std::clamp(static_cast<int>(std::floor(P.y[k] * s.grid.inv_dx)), 0, rows - 1);
    row_rate_[row] += P.dep[k];
    row_vy_[row] += P.vy[k];
    ++row_count_[row];
  }
  Frame f;
  f.eps = eps_end;
  f.sigma_top = -s.clock.top_impulse / (frame_time * area);
  f.sigma_bottom = s.clock.bottom_impulse / (frame_time * area);
  f.kinetic_energy = 0.5 * P.mass * kinetic;
  f.plate_work = s.clock.plate_work;
  f.plastic_fraction = P.n ? static_cast<double>(plastic) / P.n : 0.0;
  f.max_speed = std::sqrt(max_v2) / su.V;
  out.frames.push_back(f);
  // Plastic strain rate |d eps_P / dt| / (V / h0) = (row mean of d eps_P) / d_eps.
  for (int r = 0; r < rows; ++r) {
    const int n = row_count_[r];
    out.spacetime.values.push_back(static_cast<float>(n ? row_rate_[r] / n / d_eps : 0.0));
    out.velocity.values.push_back(static_cast<float>(n ? row_vy_[r] / n / su.V : 0.0));
  }
  ++out.spacetime.n_frames;
  ++out.velocity.n_frames;

  std::fill(P.dep.begin(), P.dep.end(), 0.0);
  s.clock.top_impulse = 0.0;
  s.clock.bottom_impulse = 0.0;
}

}  // namespace compaction
