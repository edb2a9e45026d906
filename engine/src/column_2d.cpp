#include "column_2d.hpp"

#include <fstream>

#include "scene_builder.hpp"
#include "stability.hpp"

namespace compaction {

Column2D::Column2D(const SceneParams& p, const RunControl& control)
    : p_(p), s_(build_scene(p)), pool_(p.threads), recorder_(p, s_, control.movie_file) {}

RunResult Column2D::start() const {
  RunResult r;
  r.n_particles = static_cast<std::int64_t>(s_.particles.n);
  r.grid_nx = s_.grid.nx;
  r.grid_ny = s_.grid.ny;
  r.dx = s_.grid.dx;
  r.phi_discrete = s_.particles.n * s_.particles.vol0 / (p_.width() * p_.h0);
  r.spacetime.n_rows = s_.grid.cells_y;
  r.spacetime.row_height = s_.grid.dx;
  r.velocity.n_rows = r.spacetime.n_rows;
  r.velocity.row_height = s_.grid.dx;
  return r;
}

// A generous bound on the step count: a healthy run needs t_end / dt_cfl steps; one whose time
// step collapses is stopped instead of running forever.
double Column2D::step_limit(double t_end) const {
  return 20.0 * t_end / cfl_time_step(p_.cfl, s_.grid.dx, s_.setup.c_p, s_.setup.V) + 1000.0;
}

std::string Column2D::check_frame(const Frame& f) const { return compaction::check_frame(s_, f); }

void Column2D::resume(const RunControl& control, RunResult& r, RunPosition& at) {
  std::string movie;
  const CheckpointInfo resumed = restore_checkpoint(control.resume_file, p_, s_, r, at, &movie);
  recorder_.resume_snapshots(at.snapshots_passed);
  if (at.movie_frames > 0 && !control.movie_file.empty()) {
    // the movie as the checkpoint had it, then the recorder goes on after its frames
    std::ofstream(control.movie_file, std::ios::binary | std::ios::trunc) << movie;
    recorder_.resume_movie(at.movie_frames);
  }
  if (control.on_resume) control.on_resume(resumed);
}

void Column2D::checkpoint(const RunControl& control, const RunResult& r, RunPosition at) {
  at.snapshots_passed = recorder_.snapshots_passed();
  at.movie_frames = recorder_.movie_frames();
  const CheckpointInfo info = write_checkpoint(control.checkpoint_file, p_, s_, r, at, control.movie_file);
  if (control.on_checkpoint) control.on_checkpoint(info);
}

}  // namespace compaction
