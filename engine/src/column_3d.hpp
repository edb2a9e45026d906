// The 3D column (geometry pseudo1d_3d) as the run loop drives it (run_loop.hpp): its state,
// frame recorder and step (step_3d.cpp). Its RunResult has the 2D run's frames and maps
// (diagnostics_3d.hpp); grid_nx counts the nodes across (x and z alike), grid_ny those along y.
// Threads as 2D's (the scene's threads); checkpoints as 2D's (checkpoint_3d.hpp); never a movie
// or snapshots (validate() asks movie_d_eps = 0 and no snapshot strains).
#pragma once

#include <string>

#include "checkpoint_3d.hpp"
#include "compaction/run_control.hpp"
#include "diagnostics_3d.hpp"
#include "state_3d.hpp"
#include "step_3d.hpp"
#include "thread_pool.hpp"

namespace compaction {

class Column3D {
 public:
  Column3D(const SceneParams& p, const RunControl& control);

  RunResult start() const;
  double step_limit(double t_end) const;
  StepOutcome step(double t_frame_end, StageTimes& times) {
    return advance_step_3d(s_, t_frame_end, p_.cfl, pool_, times);
  }
  void record(double eps_begin, double eps_end, RunResult& r) { recorder_.record(s_, eps_begin, eps_end, r); }
  std::string check_frame(const Frame& f) const;
  const Clock& clock() const { return s_.clock; }
  std::size_t particles() const { return s_.particles.n; }

  // Goes on from control.resume_file: the state, the result so far and the loop's position.
  void resume(const RunControl& control, RunResult& r, RunPosition& at);
  // Writes control.checkpoint_file with the loop's position `at`.
  void checkpoint(const RunControl& control, const RunResult& r, RunPosition at);

  const State3D& state() const { return s_; }  // for tests: the particles a run ends with

 private:
  const SceneParams& p_;
  State3D s_;
  ThreadPool pool_;
  FrameRecorder3D recorder_;
};

}  // namespace compaction
