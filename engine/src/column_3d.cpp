#include "column_3d.hpp"

#include "scene_builder_3d.hpp"
#include "stability_3d.hpp"

namespace compaction {

Column3D::Column3D(const SceneParams& p, const RunControl&)
    : p_(p), s_(build_scene_3d(p)), pool_(p.threads), recorder_(s_) {}

RunResult Column3D::start() const {
  RunResult r;
  r.n_particles = static_cast<std::int64_t>(s_.particles.n);
  r.grid_nx = s_.grid.nx;
  r.grid_ny = s_.grid.ny;
  r.dx = s_.grid.dx;
  r.phi_discrete = s_.particles.n * s_.particles.vol0 / (s_.setup.width * s_.setup.width * p_.h0);
  r.spacetime.n_rows = r.velocity.n_rows = s_.grid.cells_y;
  r.spacetime.row_height = r.velocity.row_height = s_.grid.dx;
  return r;
}

// A generous bound on the step count, as 2D's: 20 times what a healthy run needs.
double Column3D::step_limit(double t_end) const {
  return 20.0 * t_end / cfl_time_step(p_.cfl, s_.grid.dx, s_.setup.c_p, s_.setup.V) + 1000.0;
}

std::string Column3D::check_frame(const Frame& f) const { return check_frame_3d(s_, f); }

// The recorder holds no state between frames (it clears its rows in each), so the state, the
// result and the position are all a resumed run needs.
void Column3D::resume(const RunControl& control, RunResult& r, RunPosition& at) {
  const CheckpointInfo resumed = restore_checkpoint_3d(control.resume_file, p_, s_, r, at);
  if (control.on_resume) control.on_resume(resumed);
}

void Column3D::checkpoint(const RunControl& control, const RunResult& r, RunPosition at) {
  const CheckpointInfo info = write_checkpoint_3d(control.checkpoint_file, p_, s_, r, at);
  if (control.on_checkpoint) control.on_checkpoint(info);
}

}  // namespace compaction
