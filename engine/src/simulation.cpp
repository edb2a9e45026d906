// The run loop: build the scene (or restore a checkpoint over it), step until the imposed strain
// reaches eps_end (frames fall on exact multiples of d_eps), record each frame, check
// stability, report progress, write checkpoints between steps when they fall due.
#include "compaction/simulation.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "checkpoint.hpp"
#include "diagnostics.hpp"
#include "scene_builder.hpp"
#include "simulation_3d.hpp"
#include "stability.hpp"
#include "stages.hpp"
#include "step.hpp"

namespace compaction {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What the scene fixes of the result before the first step: counts, the grid, the maps' rows.
RunResult start_result(const SceneParams& p, const State& s) {
  RunResult r;
  r.n_particles = static_cast<std::int64_t>(s.particles.n);
  r.grid_nx = s.grid.nx;
  r.grid_ny = s.grid.ny;
  r.dx = s.grid.dx;
  r.phi_discrete = s.particles.n * s.particles.vol0 / (p.width() * p.h0);
  r.spacetime.n_rows = s.grid.cells_y;
  r.spacetime.row_height = s.grid.dx;
  r.velocity.n_rows = r.spacetime.n_rows;
  r.velocity.row_height = s.grid.dx;
  return r;
}

// A generous bound on the step count: a healthy run needs t_end / dt_cfl steps; one whose time
// step collapses is stopped instead of running forever.
double step_limit(const SceneParams& p, const State& s, double t_end) {
  const double dt_cfl = p.cfl * s.grid.dx / (s.setup.c_p + s.setup.V);
  return 20.0 * t_end / dt_cfl + 1000.0;
}

// Takes the last frame back (a frame with a non-finite number, which is never stored).
void drop_last_frame(RunResult& r) {
  r.frames.pop_back();
  r.spacetime.values.resize(r.spacetime.values.size() - r.spacetime.n_rows);
  --r.spacetime.n_frames;
  r.velocity.values.resize(r.velocity.values.size() - r.velocity.n_rows);
  --r.velocity.n_frames;
}

}  // namespace

RunResult run_scene(const SceneParams& p, const RunControl& control) {
  if (const auto errors = validate(p); !errors.empty()) {
    throw std::invalid_argument(errors[0].field + ": " + errors[0].message);
  }
  if (p.geometry == Geometry::pseudo1d_3d) return run_column_3d(p, control);  // simulation_3d.cpp
  const auto t0 = std::chrono::steady_clock::now();
  State s = build_scene(p);
  ThreadPool pool(p.threads);
  FrameRecorder recorder(p, s, control.movie_file);

  RunResult r = start_result(p, s);
  RunPosition at;  // where the loop stands; a resumed run takes it from the checkpoint
  if (!control.resume_file.empty()) {
    std::string movie;
    const CheckpointInfo resumed = restore_checkpoint(control.resume_file, p, s, r, at, &movie);
    recorder.resume_snapshots(at.snapshots_passed);
    if (at.movie_frames > 0 && !control.movie_file.empty()) {
      // the movie as the checkpoint had it, then the recorder goes on after its frames
      std::ofstream(control.movie_file, std::ios::binary | std::ios::trunc) << movie;
      recorder.resume_movie(at.movie_frames);
    }
    if (control.on_resume) control.on_resume(resumed);
  }

  const double V = s.setup.V, h0 = p.h0;
  const double eps_end = p.eps_final();
  const double t_end = eps_end * h0 / V;
  const double max_steps = step_limit(p, s, t_end);

  auto stop = [&](RunStatus status, std::string reason) {
    r.status = status;
    r.reason = std::move(reason);
    r.failed_step = status == RunStatus::unstable ? s.clock.step : -1;
  };

  const auto t_loop = std::chrono::steady_clock::now();
  auto last_checkpoint = t_loop;
  // Between two steps: the state a checkpoint holds (it changes nothing of the run).
  auto checkpoint = [&] {
    at.snapshots_passed = recorder.snapshots_passed();
    at.movie_frames = recorder.movie_frames();
    RunPosition saved = at;
    saved.wall_seconds += seconds_since(t0);
    saved.loop_seconds += seconds_since(t_loop);
    const CheckpointInfo info =
        write_checkpoint(control.checkpoint_file, p, s, r, saved, control.movie_file);
    last_checkpoint = std::chrono::steady_clock::now();
    if (control.on_checkpoint) control.on_checkpoint(info);
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
    double dt = stable_dt(s, p.cfl);
    const bool closes_frame = s.clock.t + dt >= t_frame_end;
    if (closes_frame) dt = t_frame_end - s.clock.t;

    advance_step(s, dt, pool, r.stage_seconds);
    if (closes_frame) s.clock.t = t_frame_end;  // frames fall on exact strains

    if (std::string why = check_step(s); !why.empty()) {
      stop(RunStatus::unstable, why);
      break;
    }
    if (s.clock.step > max_steps) {
      stop(RunStatus::unstable, "time step collapsed: step limit reached");
      break;
    }
    if (!closes_frame) continue;

    const auto td = std::chrono::steady_clock::now();
    recorder.record(s, at.eps_frame_begin, eps_frame_end, r);
    r.stage_seconds.diagnostics += seconds_since(td);
    r.eps_reached = eps_frame_end;
    if (std::string why = check_frame(s, r.frames.back()); !why.empty()) {
      const Frame& f = r.frames.back();
      if (!std::isfinite(f.sigma_top + f.sigma_bottom + f.kinetic_energy)) {
        drop_last_frame(r);  // the last finite frame is the last one kept
        r.eps_reached = at.eps_frame_begin;
      }
      stop(RunStatus::unstable, why);
      break;
    }
    if (control.on_progress) {
      control.on_progress({eps_frame_end, eps_end, s.clock.step, at.wall_seconds + seconds_since(t0)});
    }
    at.eps_frame_begin = eps_frame_end;
    ++at.frame;
    if (eps_frame_end >= eps_end) break;
  }

  r.steps = s.clock.step;
  r.dt_mean = r.steps ? s.clock.t / r.steps : 0.0;
  r.wall_seconds = at.wall_seconds + seconds_since(t0);
  const double loop_seconds = at.loop_seconds + seconds_since(t_loop);
  r.ns_per_particle_step =
      r.steps && s.particles.n ? 1e9 * loop_seconds / (static_cast<double>(r.steps) * s.particles.n)
                               : 0.0;
  return r;
}

}  // namespace compaction
