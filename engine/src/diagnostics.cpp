// Frame diagnostics. The space-time map is the paper's observable: the plastic Hencky strain
// rate magnitude averaged over each horizontal row of the current configuration (full 2D: not
// over the 10 % of the width next to each side wall), normalised by V / h0. Over a frame of
// imposed strain d_eps, a particle's mean rate / (V/h0) is its plastic increment / d_eps.
#include "diagnostics.hpp"

#include <algorithm>
#include <cmath>

namespace compaction {

FrameRecorder::FrameRecorder(const SceneParams& p, const State& s, const std::string& movie_file) {
  const bool walls = p.geometry == Geometry::full2d;
  x_lo_ = walls ? 0.1 * p.width() : -1e300;
  x_hi_ = walls ? 0.9 * p.width() : 1e300;
  const int rows = s.grid.cells_y;
  row_sum_.assign(rows, 0.0);
  row_vy_.assign(rows, 0.0);
  row_count_.assign(rows, 0);
  mid_sum_.assign(s.setup.n_struts, 0.0);
  end_sum_.assign(s.setup.n_struts, 0.0);
  mid_n_.assign(s.setup.n_struts, 0);
  end_n_.assign(s.setup.n_struts, 0);
  snapshots_due_ = p.snapshot_eps;
  std::sort(snapshots_due_.begin(), snapshots_due_.end());
  if (!movie_file.empty() && p.movie_d_eps > 0.0) {
    movie_ = std::make_unique<MovieRecorder>(movie_file, p, s);
  }
}

void FrameRecorder::record(State& s, double eps_begin, double eps_end, RunResult& out) {
  const Setup& su = s.setup;
  const Particles& P = s.particles;
  const double d_eps = eps_end - eps_begin;
  const double frame_time = d_eps * su.h0 / su.V;
  const ParticleTotals totals = sum_particles(s);
  const Deflections defl = strut_deflections(su.strut_thickness);

  Frame f;
  f.eps = eps_end;
  f.sigma_top = -s.clock.top_impulse / (frame_time * su.width);
  f.sigma_bottom = s.clock.bottom_impulse / (frame_time * su.width);
  f.kinetic_energy = 0.5 * P.mass * totals.kinetic;
  f.plate_work = s.clock.plate_work;
  f.plastic_fraction = P.n ? static_cast<double>(totals.plastic) / P.n : 0.0;
  f.max_deflection = defl.max;
  f.rms_deflection = defl.rms;
  f.max_speed = std::sqrt(totals.max_v2) / su.V;
  out.frames.push_back(f);
  append_map_rows(out, d_eps, su.V);
  take_snapshot_if_due(P, eps_end, d_eps, out);
  if (movie_) movie_->record_if_due(P, eps_end, d_eps);

  std::fill(s.particles.dep.begin(), s.particles.dep.end(), 0.0);
  s.clock.top_impulse = 0.0;
  s.clock.bottom_impulse = 0.0;
}

FrameRecorder::ParticleTotals FrameRecorder::sum_particles(State& s) {
  const Setup& su = s.setup;
  Particles& P = s.particles;
  const int rows = static_cast<int>(row_sum_.size());
  const double inv_row = 1.0 / s.grid.dx;
  std::fill(row_sum_.begin(), row_sum_.end(), 0.0);
  std::fill(row_vy_.begin(), row_vy_.end(), 0.0);
  std::fill(row_count_.begin(), row_count_.end(), 0);
  std::fill(mid_sum_.begin(), mid_sum_.end(), 0.0);
  std::fill(end_sum_.begin(), end_sum_.end(), 0.0);
  std::fill(mid_n_.begin(), mid_n_.end(), 0);
  std::fill(end_n_.begin(), end_n_.end(), 0);

  ParticleTotals t;
  for (std::size_t k = 0; k < P.n; ++k) {
    P.ep[k] += P.dep[k];
    const double v2 = P.vx[k] * P.vx[k] + P.vy[k] * P.vy[k];
    t.kinetic += v2;
    t.max_v2 = std::max(t.max_v2, v2);
    if (P.dep[k] > 0.0) ++t.plastic;
    if (P.x[k] >= x_lo_ && P.x[k] < x_hi_) {
      const int row = std::clamp(static_cast<int>(std::floor(P.y[k] * inv_row)), 0, rows - 1);
      row_sum_[row] += P.dep[k];
      row_vy_[row] += P.vy[k];
      ++row_count_[row];
    }
    if (P.strut[k] >= 0) {
      double u = P.x[k] - P.x0[k];  // lateral displacement, nearest periodic image
      if (s.grid.periodic_x) u -= su.width * std::round(u / su.width);
      if (P.strut_mid[k]) mid_sum_[P.strut[k]] += u, ++mid_n_[P.strut[k]];
      else end_sum_[P.strut[k]] += u, ++end_n_[P.strut[k]];
    }
  }
  return t;
}

// A strut's deflection: the mean lateral displacement of its middle half against its ends.
FrameRecorder::Deflections FrameRecorder::strut_deflections(double strut_thickness) const {
  double max_defl = 0.0, sum_defl2 = 0.0;
  int struts = 0;
  for (std::size_t i = 0; i < mid_sum_.size(); ++i) {
    if (mid_n_[i] == 0 || end_n_[i] == 0) continue;
    const double d = (mid_sum_[i] / mid_n_[i] - end_sum_[i] / end_n_[i]) / strut_thickness;
    max_defl = std::max(max_defl, std::abs(d));
    sum_defl2 += d * d;
    ++struts;
  }
  return {max_defl, struts ? std::sqrt(sum_defl2 / struts) : 0.0};
}

// One row of each map: the rows' mean plastic strain rate / (V / h0) and mean vy / V.
void FrameRecorder::append_map_rows(RunResult& out, double d_eps, double V) const {
  const int rows = static_cast<int>(row_sum_.size());
  SpaceTimeMap& map = out.spacetime;
  for (int r = 0; r < rows; ++r) {
    const double rate = row_count_[r] ? row_sum_[r] / row_count_[r] / d_eps : 0.0;
    map.values.push_back(static_cast<float>(rate));
  }
  ++map.n_frames;
  SpaceTimeMap& vel = out.velocity;
  for (int r = 0; r < rows; ++r) {
    vel.values.push_back(static_cast<float>(row_count_[r] ? row_vy_[r] / row_count_[r] / V : 0.0));
  }
  ++vel.n_frames;
}

void FrameRecorder::take_snapshot_if_due(const Particles& P, double eps_end, double d_eps,
                                         RunResult& out) {
  const auto due = [&] {
    return next_snapshot_ < snapshots_due_.size() &&
           eps_end >= snapshots_due_[next_snapshot_] - 1e-9;
  };
  if (!due()) return;
  Snapshot snap;
  snap.eps = eps_end;
  snap.x.assign(P.x.begin(), P.x.end());
  snap.y.assign(P.y.begin(), P.y.end());
  snap.strain_rate.resize(P.n);
  snap.plastic_strain.assign(P.ep.begin(), P.ep.end());
  snap.jacobian.resize(P.n);
  for (std::size_t k = 0; k < P.n; ++k) {
    snap.strain_rate[k] = static_cast<float>(P.dep[k] / d_eps);
    const Mat2 F = P.Fe[k];
    snap.jacobian[k] = static_cast<float>(F.xx * F.yy - F.xy * F.yx);  // det Fp = 1
  }
  out.snapshots.push_back(std::move(snap));
  while (due()) ++next_snapshot_;  // one snapshot for every due strain this frame passed
}

}  // namespace compaction
