// What a frame of the 3D column records, in the 2D run's units and layout so that the
// classifier and the service read it unchanged: plate stresses (impulse per plate area and
// time), kinetic energy, plate work, the share of yielding particles, the largest speed, and
// the space-time maps of the row-averaged plastic strain rate and vertical velocity, a row
// being a grid layer (dx tall) and the average running over x and z. Strut deflections are a
// 2D diagnostic: 0 here.
#pragma once

#include <vector>

#include "compaction/result.hpp"
#include "state_3d.hpp"

namespace compaction {

class FrameRecorder3D {
 public:
  explicit FrameRecorder3D(const State3D& s);
  // Appends the frame that ends at imposed strain eps_end (begun at eps_begin) to `out`, then
  // starts the next one (clears the frame's plastic strain and plate impulses).
  void record(State3D& s, double eps_begin, double eps_end, RunResult& out);

 private:
  std::vector<double> row_rate_, row_vy_;
  std::vector<int> row_count_;
};

}  // namespace compaction
