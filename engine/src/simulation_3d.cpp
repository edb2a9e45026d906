#include "simulation_3d.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "diagnostics_3d.hpp"
#include "scene_builder_3d.hpp"
#include "stages_3d.hpp"
#include "step_3d.hpp"

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

RunResult run_column_3d(const SceneParams& p, const RunControl& control) {
  if (!control.checkpoint_file.empty() || !control.resume_file.empty()) {
    throw std::invalid_argument("geometry: pseudo1d_3d has no checkpoints (yet)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  State3D s = build_scene_3d(p);
  FrameRecorder3D recorder(s);
  RunResult r;
  r.n_particles = static_cast<std::int64_t>(s.particles.n);
  r.grid_nx = s.grid.nx;
  r.grid_ny = s.grid.ny;
  r.dx = s.grid.dx;
  r.phi_discrete = s.particles.n * s.particles.vol0 / (s.setup.width * s.setup.width * p.h0);
  r.spacetime.n_rows = r.velocity.n_rows = s.grid.cells_y;
  r.spacetime.row_height = r.velocity.row_height = s.grid.dx;

  const double V = s.setup.V, h0 = p.h0, eps_end = p.eps_final();
  const double t_end = eps_end * h0 / V;
  // A generous bound on the step count, as 2D's: 20 times what a healthy run needs.
  const double max_steps = 20.0 * t_end / (p.cfl * s.grid.dx / (s.setup.c_p + V)) + 1000.0;
  int frame = 0;
  double eps_frame_begin = 0.0;
  const auto t_loop = std::chrono::steady_clock::now();
  while (true) {
    if (control.cancel && control.cancel->load(std::memory_order_relaxed)) {
      r.status = RunStatus::cancelled, r.reason = "cancelled on request";
      break;
    }
    const double eps_frame_end = std::min(eps_end, (frame + 1) * p.d_eps);
    const double t_frame_end = std::min(t_end, eps_frame_end * h0 / V);
    double dt = stable_dt_3d(s, p.cfl);
    const bool closes_frame = s.clock.t + dt >= t_frame_end;
    if (closes_frame) dt = t_frame_end - s.clock.t;
    advance_step_3d(s, dt, r.stage_seconds);
    if (closes_frame) s.clock.t = t_frame_end;  // frames fall on exact strains
    if (std::string why = check_step_3d(s); !why.empty()) {
      r.status = RunStatus::unstable, r.reason = why, r.failed_step = s.clock.step;
      break;
    }
    if (s.clock.step > max_steps) {
      r.status = RunStatus::unstable, r.reason = "time step collapsed: step limit reached";
      r.failed_step = s.clock.step;
      break;
    }
    if (!closes_frame) continue;
    recorder.record(s, eps_frame_begin, eps_frame_end, r);
    r.eps_reached = eps_frame_end;
    if (std::string why = check_frame_3d(s, r.frames.back()); !why.empty()) {
      const Frame& f = r.frames.back();
      if (!std::isfinite(f.sigma_top + f.sigma_bottom + f.kinetic_energy)) {
        // the last finite frame is the last one kept (as 2D's drop_last_frame)
        r.frames.pop_back();
        r.spacetime.values.resize(r.spacetime.values.size() - r.spacetime.n_rows);
        --r.spacetime.n_frames;
        r.velocity.values.resize(r.velocity.values.size() - r.velocity.n_rows);
        --r.velocity.n_frames;
        r.eps_reached = eps_frame_begin;
      }
      r.status = RunStatus::unstable, r.reason = why, r.failed_step = s.clock.step;
      break;
    }
    if (control.on_progress) {
      control.on_progress({eps_frame_end, eps_end, s.clock.step,
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
    }
    eps_frame_begin = eps_frame_end;
    ++frame;
    if (eps_frame_end >= eps_end) break;
  }
  r.steps = s.clock.step;
  r.dt_mean = r.steps > 0 ? s.clock.t / r.steps : 0.0;
  const auto now = std::chrono::steady_clock::now();
  r.wall_seconds = std::chrono::duration<double>(now - t0).count();
  const double loop_seconds = std::chrono::duration<double>(now - t_loop).count();
  const double particle_steps = static_cast<double>(r.steps) * s.particles.n;
  r.ns_per_particle_step = particle_steps > 0 ? 1e9 * loop_seconds / particle_steps : 0.0;
  return r;
}

}  // namespace compaction
