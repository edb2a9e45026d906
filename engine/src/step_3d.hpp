// One explicit time step of the 3D column.
#pragma once

#include "compaction/result.hpp"  // StageTimes
#include "state_3d.hpp"

namespace compaction {

void advance_step_3d(State3D& s, double dt, StageTimes& times);

}  // namespace compaction
