// The 2D scene (pseudo-1D and full 2D) as the run loop drives it (run_loop.hpp): its state,
// threads and frame recorder, its step (step.cpp), its checkpoints.
#pragma once

#include <string>

#include "checkpoint.hpp"
#include "compaction/run_control.hpp"
#include "diagnostics.hpp"
#include "state.hpp"
#include "step.hpp"
#include "thread_pool.hpp"

namespace compaction {

class Column2D {
 public:
  Column2D(const SceneParams& p, const RunControl& control);

  RunResult start() const;
  double step_limit(double t_end) const;
  StepOutcome step(double t_frame_end, StageTimes& times) {
    return advance_step(s_, t_frame_end, p_.cfl, pool_, times);
  }
  void record(double eps_begin, double eps_end, RunResult& r) { recorder_.record(s_, eps_begin, eps_end, r); }
  std::string check_frame(const Frame& f) const;
  const Clock& clock() const { return s_.clock; }
  std::size_t particles() const { return s_.particles.n; }

  // Goes on from control.resume_file: the state, the result so far and the loop's position.
  void resume(const RunControl& control, RunResult& r, RunPosition& at);
  // Writes control.checkpoint_file with the loop's position `at`.
  void checkpoint(const RunControl& control, const RunResult& r, RunPosition at);

 private:
  const SceneParams& p_;
  State s_;
  ThreadPool pool_;
  FrameRecorder recorder_;
};

}  // namespace compaction
