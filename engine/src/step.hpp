// One explicit MPM time step.
#pragma once

#include "compaction/result.hpp"
#include "state.hpp"
#include "thread_pool.hpp"

namespace compaction {

void advance_step(State& s, double dt, ThreadPool& pool, StageTimes& times);

}  // namespace compaction
