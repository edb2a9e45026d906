// One explicit time step of the 3D column, the whole of it (step_3d.cpp is its recipe).
#pragma once

#include "compaction/result.hpp"  // StageTimes
#include "state_3d.hpp"
#include "step_helpers.hpp"
#include "thread_pool.hpp"

namespace compaction {

// The CFL time step, shortened when it would pass t_frame_end (frames end on their exact
// strain), the transfers, the clock and the stability check, as advance_step in 2D.
StepOutcome advance_step_3d(State3D& s, double t_frame_end, double cfl, ThreadPool& pool,
                            StageTimes& times);

}  // namespace compaction
