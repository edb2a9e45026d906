// Front detection and tracking in the space-time map of the plastic strain rate.
//
// A frame of the map is a profile of plastic activity over the rows (height in the current
// configuration). In each frame the tracker finds the active segments (rows above a threshold),
// then links the segments of consecutive frames into fronts: a segment continues the front whose
// predicted interval it overlaps or comes closest to (within a tolerance), one segment per front.
// A front records where it started (top plate, bottom plate, interior), its positions, its turning
// points, the reflections at the plates among them, and the speed of its leading edge before the
// first turn. Its thresholds are TrackerSettings (settings.hpp).
#pragma once

#include <array>
#include <vector>

#include "compaction/classify/settings.hpp"
#include "compaction/result.hpp"

namespace compaction::classify {

// Where a front begins or turns.
enum class Origin { top, bottom, interior };
const char* to_string(Origin o);

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
                                       // positive in the direction of propagation: the
                                       // least-squares slope (NaN if too few points)     [-]
  double speed_error = 0.0;            // its standard error from the edge's scatter      [-]
  double transit_speed = 0.0;          // the same leg's mean speed: the edge's travel between
                                       // the first and last points of the fit / the strain
                                       // it took (NaN if too few points)                 [-]
  double transit_error = 0.0;          // its uncertainty: each end known to a row, to the
                                       // edge's step of a unit cell (sd cell / sqrt(12))
                                       // and to half a frame                             [-]
  // The leading-edge points that both readings of the speed use, (eps, height [h0]) in time
  // order: the leg before the first turn, away from the plates, without shared segments.
  std::vector<std::array<double, 2>> leg_edge;
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
