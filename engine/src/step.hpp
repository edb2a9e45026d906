// One explicit MPM time step of the 2D scene, the whole of it (step.cpp is its recipe).
#pragma once

#include "compaction/result.hpp"
#include "state.hpp"
#include "step_helpers.hpp"
#include "thread_pool.hpp"

namespace compaction {

// The CFL time step, shortened when it would pass t_frame_end (frames end on their exact
// strain), the transfers, the clock and the stability check.
StepOutcome advance_step(State& s, double t_frame_end, double cfl, ThreadPool& pool,
                         StageTimes& times);

}  // namespace compaction
