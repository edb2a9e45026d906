// The run loop, the same for every geometry: step until the imposed strain reaches eps_end,
// with frames on exact multiples of d_eps, each frame recorded and checked, progress reported,
// checkpoints written between steps when they fall due, and a run that goes unstable stopped
// with its reason. A column (column_2d.hpp, column_3d.hpp) brings its scene and its step:
//   RunResult start() const                         what the scene fixes before the first step
//   double step_limit(double t_end) const           a bound on the steps of a healthy run
//   StepOutcome step(double t_frame_end, StageTimes&)  one whole step (step.cpp, step_3d.cpp)
//   void record(double eps_begin, double eps_end, RunResult&)  closes a frame
//   std::string check_frame(const Frame&) const     why the frame makes the run unusable
//   const Clock& clock() const, std::size_t particles() const
//   void resume(const RunControl&, RunResult&, RunPosition&)     goes on from resume_file
//   void checkpoint(const RunControl&, const RunResult&, const RunPosition&)  writes one
#pragma once

#include <chrono>
#include <cmath>
#include <string>

#include "checkpoint.hpp"
#include "compaction/run_control.hpp"
#include "step_helpers.hpp"

namespace compaction {

namespace run_loop_detail {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Takes the last frame back (a frame with a non-finite number, which is never stored).
inline void drop_last_frame(RunResult& r) {
  r.frames.pop_back();
  r.spacetime.values.resize(r.spacetime.values.size() - r.spacetime.n_rows);
  --r.spacetime.n_frames;
  r.velocity.values.resize(r.velocity.values.size() - r.velocity.n_rows);
  --r.velocity.n_frames;
}

}  // namespace run_loop_detail

// t0: when the run began (the column's construction counts as run time).
template <class Column>
RunResult run_loop(const SceneParams& p, const RunControl& control, Column& c,
                   std::chrono::steady_clock::time_point t0) {
  using run_loop_detail::seconds_since;
  RunResult r = c.start();
  RunPosition at;  // where the loop stands; a resumed run takes it from the checkpoint
  if (!control.resume_file.empty()) c.resume(control, r, at);

  const double V = p.plate_speed(), h0 = p.h0;
  const double eps_end = p.eps_final();
  const double t_end = eps_end * h0 / V;
  const double max_steps = c.step_limit(t_end);

  auto stop = [&](RunStatus status, std::string reason) {
    r.status = status;
    r.reason = std::move(reason);
    r.failed_step = status == RunStatus::unstable ? c.clock().step : -1;
  };

  const auto t_loop = std::chrono::steady_clock::now();
  auto last_checkpoint = t_loop;
  // Between two steps: the state a checkpoint holds (it changes nothing of the run).
  auto checkpoint = [&] {
    RunPosition saved = at;
    saved.wall_seconds += seconds_since(t0);
    saved.loop_seconds += seconds_since(t_loop);
    c.checkpoint(control, r, saved);
    last_checkpoint = std::chrono::steady_clock::now();
  };
  while (true) {
    const bool cancelled = control.cancel && control.cancel->load(std::memory_order_relaxed);
    if (!control.checkpoint_file.empty() &&
        (cancelled || (control.checkpoint_every > 0 &&
                       seconds_since(last_checkpoint) >= control.checkpoint_every))) {
      checkpoint();
    }
    if (cancelled) {
      stop(RunStatus::cancelled, "cancelled on request");
      break;
    }
    const double eps_frame_end = std::min(eps_end, (at.frame + 1) * p.d_eps);
    const double t_frame_end = std::min(t_end, eps_frame_end * h0 / V);

    const StepOutcome step = c.step(t_frame_end, r.stage_seconds);
    if (!step.problem.empty()) {
      stop(RunStatus::unstable, step.problem);
      break;
    }
    if (c.clock().step > max_steps) {
      stop(RunStatus::unstable, "time step collapsed: step limit reached");
      break;
    }
    if (!step.closes_frame) continue;

    timed(r.stage_seconds.diagnostics, [&] { c.record(at.eps_frame_begin, eps_frame_end, r); });
    r.eps_reached = eps_frame_end;
    if (std::string why = c.check_frame(r.frames.back()); !why.empty()) {
      const Frame& f = r.frames.back();
      if (!std::isfinite(f.sigma_top + f.sigma_bottom + f.kinetic_energy)) {
        run_loop_detail::drop_last_frame(r);  // the last finite frame is the last one kept
        r.eps_reached = at.eps_frame_begin;
      }
      stop(RunStatus::unstable, why);
      break;
    }
    if (control.on_progress) {
      control.on_progress({eps_frame_end, eps_end, c.clock().step, at.wall_seconds + seconds_since(t0)});
    }
    at.eps_frame_begin = eps_frame_end;
    ++at.frame;
    if (eps_frame_end >= eps_end) break;
  }

  r.steps = c.clock().step;
  r.dt_mean = r.steps ? c.clock().t / r.steps : 0.0;
  r.wall_seconds = at.wall_seconds + seconds_since(t0);
  const double loop_seconds = at.loop_seconds + seconds_since(t_loop);
  const double particle_steps = static_cast<double>(r.steps) * static_cast<double>(c.particles());
  r.ns_per_particle_step = particle_steps > 0 ? 1e9 * loop_seconds / particle_steps : 0.0;
  return r;
}

}  // namespace compaction
