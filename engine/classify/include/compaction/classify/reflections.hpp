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

// The speed of one edge of the band over its early stage: c/V = -(1/h0) d(height)/d eps, the
// least-squares slope, and its standard error from the edge's scatter about the line.
struct EdgeSpeed {
  double speed = 0.0;  // NaN: fewer than min_fit_points heights
  double error = 0.0;  // NaN: fewer than three heights
};

struct BandPath {
  std::vector<double> height;   // per frame: the band's height / h0 (NaN: no material)
  int n_reflections = 0;        // turns at a plate
  int n_turns = 0;              // all turns, at a plate or not
  double first_reflection_eps = 0.0;  // strain of the first turn (NaN: none)
  // The band's early stage (early_stage): its first leg, before the first turn, while the edge
  // is in the column's upper part and fit_margin below the plate. A band is a step of the row
  // velocity, from the material ahead of it to the plate speed; where the step is sharp its
  // edges run together, where it widens its leading edge runs ahead of its middle.
  EdgeSpeed middle;             // the band's middle, `height` above: where the rows fall below
                                // half the plate speed
  EdgeSpeed lead;               // the leading edge: the step's lead_share point above the
                                // material ahead (the median row velocity between the bottom
                                // plate zone and a unit cell below the band's middle)
};

// Follows the band through the velocity map (frames x rows, velocity / V). Turns need the band
// to go back by turn_travel unit cells; a turn nearer to a plate than that is a reflection. The
// rows within plate_zone of the top plate are not read (they ring with it). The early stage's
// edge speeds are read over the frames before the first turn.
BandPath follow_band(const SpaceTimeMap& velocity, const MapAxes& axes, const TrackerSettings& s);

}  // namespace compaction::classify
