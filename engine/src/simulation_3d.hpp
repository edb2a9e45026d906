// The run loop of the 3D column: steps at the CFL time step, frames every d_eps of imposed
// strain (a frame's last step shortened to end on it), stability checks after every step, until
// eps_end. Its RunResult has the 2D run's frames and maps (diagnostics_3d.hpp); grid_nx counts
// the nodes across (x and z alike), grid_ny those along y.
#pragma once

#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "compaction/simulation.hpp"  // RunControl
#include "state_3d.hpp"

namespace compaction {

// Why the last step left the 3D column unusable (empty when it did not): an inverted or
// non-finite Fe, a particle as fast as the P-wave, a particle within 1.4 cells of the grid's
// top or bottom edge (its stencil would leave the grid). As stability.cpp's check_step.
std::string check_step_3d(const State3D& s);

// Why the frame just recorded makes the run unusable (empty when it does not), as
// stability.cpp's check_frame: a non-finite plate stress or kinetic energy, or kinetic energy
// above twice the plates' work plus 1 % of that of the whole specimen moving at V.
std::string check_frame_3d(const State3D& s, const Frame& f);

// Runs the column of p (geometry pseudo1d_3d, valid). Of `control` it serves on_progress and
// cancel; checkpoints (checkpoint_file, resume_file) are not implemented for the 3D state and
// throw std::invalid_argument; a movie is never recorded (validate() asks movie_d_eps = 0).
RunResult run_column_3d(const SceneParams& p, const RunControl& control = {});

}  // namespace compaction
