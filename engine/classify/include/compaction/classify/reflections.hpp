// Reflections of a compaction band at the plates, read from the row velocity map.
//
// A band separates material that moves with the top plate (row velocity -V) from material at
// rest: in front of a band leaving the top the column is at rest; once it reaches the bottom,
// the bottom plate stops the material and the reflected band, going up, again has rest below
// and the plate's velocity above it. So in every frame the band is where the velocity profile,
// read from the top plate down, first falls below half the plate speed; followed over frames it
// zig-zags between the plates, and each turn at a plate is one reflection. (The plastic strain
// rate map cannot show this once a band has reflected: the partly compacted rows behind it keep
// yielding as brightly as the reflected band.)
#pragma once

#include <vector>

#include "compaction/classify/fronts.hpp"
#include "compaction/result.hpp"

namespace compaction::classify {

struct BandPath {
  std::vector<double> height;   // per frame: the band's height / h0 (NaN: no material)
  int n_reflections = 0;        // turns at a plate
  int n_turns = 0;              // all turns, at a plate or not
  double first_reflection_eps = 0.0;  // strain of the first turn (NaN: none)
};

// Follows the band through the velocity map (frames x rows, velocity / V). Turns need the band
// to go back by turn_travel unit cells; a turn nearer to a plate than that is a reflection. The
// rows within plate_zone of the top plate are not read (they ring with it).
BandPath follow_band(const SpaceTimeMap& velocity, const MapAxes& axes, const TrackerSettings& s);

}  // namespace compaction::classify
