// Front detection and tracking in the space-time map of the plastic strain rate.
//
// A frame of the map is a profile of plastic activity over the rows (height in the current
// configuration). In each frame the tracker finds the active segments (rows above a threshold),
// then links the segments of consecutive frames into fronts: a segment continues the front whose
// predicted interval it overlaps or comes closest to (within a tolerance), one segment per front.
// A front records where it started (top plate, bottom plate, interior), its positions, its turning
// points, the reflections at the plates among them, and the speed of its leading edge before the
// first reflection. docs/classifier.md explains each threshold.
#pragma once

#include <vector>

#include "compaction/result.hpp"

namespace compaction::classify {

// Where a front begins or turns.
enum class Origin { top, bottom, interior };
const char* to_string(Origin o);

// Thresholds of the tracker. Lengths are in unit cells (the period of the structure), strain
// rates in units of the imposed mean rate V / h0 (the unit of the space-time map).
struct TrackerSettings {
  double rel_threshold = 0.2;   // a row is active above this share of its frame's peak      [-]
  double abs_threshold = 1.0;   // ... and above the imposed mean strain rate V/h0            [V/h0]
  double smooth = 0.125;        // half-width of the box filter over rows                   [cells]
  double merge_gap = 0.5;       // runs of active rows closer than this form one segment    [cells]
  double link_tol = 1.0;        // a segment continues a front within this distance         [cells]
  int max_missing = 3;          // frames a front may go unseen before it ends              [-]
  double plate_zone = 1.5;      // within this distance of a plate a front is "at the plate" [cells]
  double min_travel = 2.0;      // a front propagates when it travels at least this far     [cells]
  double turn_travel = 4.0;     // a turn: the front goes back at least this far            [cells]
  double max_extent = 0.5;      // a segment wider than this share of the current height is
                                // diffuse activity: it is tracked but gives no position    [-]
  double fit_margin = 1.0;      // the speed fit skips this distance next to either plate   [cells]
};

// The axes of a space-time map: the imposed strain of each frame and the lengths.
struct MapAxes {
  std::vector<double> eps;  // imposed strain at the end of each frame   [-]
  double h0 = 1.0;          // initial specimen height                   [m]
  double unit_cell = 0.0;   // side of a unit cell, h0 / n_rows          [m]
};

// Active rows of one frame; heights in units of h0 (current configuration).
struct Segment {
  int frame = 0;
  double eps = 0.0;           // imposed strain of the frame            [-]
  double lo = 0.0, hi = 0.0;  // lower and upper edge                  [h0]
  double centroid = 0.0;      // activity-weighted mean height          [h0]
  double peak = 0.0;          // largest smoothed rate in the segment   [V/h0]
  double mass = 0.0;          // sum of the rates over its rows x rows' height [V/h0 * h0]
  bool shared = false;        // also part of another front (two fronts crossing): its
                              // position is not this front's own
};

struct TurningPoint {
  int index = 0;          // index into Front::path
  double eps = 0.0;
  Origin where = Origin::interior;  // top/bottom: a reflection at that plate
};

struct Front {
  Origin origin = Origin::interior;
  std::vector<Segment> path;           // one segment per frame it was seen, in time order
  std::vector<TurningPoint> turns;     // reversals of direction by more than turn_travel
  int n_reflections = 0;               // turns at a plate
  double travel = 0.0;                 // largest distance of the centroid from its start [h0]
  double speed = 0.0;                  // leading-edge speed before the first turn / V,
                                       // positive in the direction of propagation (NaN if
                                       // too few points)                                [-]
  bool propagating = false;            // travel >= min_travel
  double start_eps() const { return path.front().eps; }
  double end_eps() const { return path.back().eps; }
  double mass() const;                 // summed activity of its segments (half of a shared one)
};

// Everything the tracker found.
struct FrontTracks {
  std::vector<std::vector<Segment>> segments;  // per frame
  std::vector<Front> fronts;                   // in order of appearance
  double total_mass = 0.0;                     // activity in all segments
};

FrontTracks track_fronts(const SpaceTimeMap& map, const MapAxes& axes,
                         const TrackerSettings& s = {});

}  // namespace compaction::classify
