// The 3D column (geometry pseudo1d_3d) as the run loop drives it (run_loop.hpp): its state,
// frame recorder and step (step_3d.cpp). Its RunResult has the 2D run's frames and maps
// (diagnostics_3d.hpp); grid_nx counts the nodes across (x and z alike), grid_ny those along y.
// One thread; no checkpoints yet (resume and checkpoint throw std::invalid_argument, and so
// does the constructor when `control` asks for them); never a movie (validate() asks
// movie_d_eps = 0).
#pragma once

#include <stdexcept>
#include <string>

#include "checkpoint.hpp"
#include "compaction/run_control.hpp"
#include "diagnostics_3d.hpp"
#include "state_3d.hpp"
#include "step_3d.hpp"

namespace compaction {

class Column3D {
 public:
  Column3D(const SceneParams& p, const RunControl& control);

  RunResult start() const;
  double step_limit(double t_end) const;
  StepOutcome step(double t_frame_end, StageTimes& times) {
    return advance_step_3d(s_, t_frame_end, p_.cfl, times);
  }
  void record(double eps_begin, double eps_end, RunResult& r) { recorder_.record(s_, eps_begin, eps_end, r); }
  std::string check_frame(const Frame& f) const;
  const Clock& clock() const { return s_.clock; }
  std::size_t particles() const { return s_.particles.n; }

  void resume(const RunControl&, RunResult&, RunPosition&) { no_checkpoints(); }
  void checkpoint(const RunControl&, const RunResult&, RunPosition) { no_checkpoints(); }

 private:
  [[noreturn]] static void no_checkpoints() {
    throw std::invalid_argument("geometry: pseudo1d_3d has no checkpoints (yet)");
  }

  const SceneParams& p_;
  State3D s_;
  FrameRecorder3D recorder_;
};

}  // namespace compaction
