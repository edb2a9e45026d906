// The features of a run that decide its class: fronts (from the tracker), plate stresses and the
// per-frame strut diagnostics. Computed only from what the run produced plus the geometry
// (phi of the particles, h0, unit cell); never from S or R.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/classify/fronts.hpp"
#include "compaction/classify/reflections.hpp"
#include "compaction/classify/settings.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"

namespace compaction::classify {

// Every feature is written to summary.json's "features" (to_json below); the dashboard shows them
// all. The first group is what the decision's rules read; the second is shown for people only
// (and checked by the tests): no rule reads it.
struct Features {
  // Read by the rules. Fronts.
  bool two_sided = false;            // a top front from the onset and a bottom front propagate
                                     // at the same time (class (c)'s crossing bands)
  std::string primary_origin;        // origin of the primary front ("" if none)
  int n_reflections = 0;             // reflections at the plates: of the band in the velocity
                                     // map (reflections.hpp), else turns of the primary front
  double first_reflection_eps = 0.0; // strain of the first reflection (NaN: none)
  double band_speed_ratio = 0.0;     // c_b / V of the primary front before its first turn (NaN:
                                     // none); the rules read it as speed_excess
  double nonreflecting_speed = 0.0;  // 1 / (1 - phi) with the particles' phi        [-]
  double speed_excess = 0.0;         // band_speed_ratio (1 - phi) - 1  (0: non-reflecting) [-]
  double arrival_eps = 0.0;          // strain at which the primary front reached the opposite
                                     // plate (NaN: it did not)                      [-]
  // Organisation of plastic activity.
  double coherence = 0.0;            // share of activity carried by propagating fronts (NaN:
                                     // no activity)                                 [-]
  double peak_jump = 0.0;            // median jump of the most active row between frames [cells]
  // Plate stresses.
  double stress_ratio = 0.0;         // median top / median bottom stress during propagation [-]
  double undulation_share = 0.0;     // share of the detrended top-stress variance at one period
                                     // per row of voids crossed                     [-]
  // Struts.
  double deflection_growth = 0.0;    // log10 of the growth of the largest strut deflection from
                                     // the first frame to the one before first yield (floored)
                                     //                                             [decades]
  double deflection_before_yield = 0.0;  // max strut deflection as first yield is reached:
                                         // the last elastic frame's, carried on at its growth
                                         // rate to where yield_fraction is crossed [thickness]

  // Shown only (no rule reads them).
  int n_fronts = 0;                  // propagating fronts (travel >= min_travel)
  int n_fronts_onset = 0;            // ... that start within onset_window of the first activity
  std::vector<std::string> onset_origins;  // where those start: top, bottom, interior
  bool top_front = false;            // a propagating front starts at the top plate
  bool bottom_front = false;         // a propagating front starts at the bottom plate
  double band_speed_error = 0.0;     // standard error of band_speed_ratio (the fit's scatter)
  double band_speed_transit = 0.0;   // c_b / V of the same leg as its mean speed: travel /
                                     // strain between its first and last points (NaN: none)
  double band_speed_transit_error = 0.0;  // its uncertainty (fronts.hpp, Front::transit_error)
  double band_speed_early = 0.0;     // c_b / V of the band's middle in the velocity map over its
                                     // early stage (reflections.hpp, BandPath::middle; NaN: none)
  double band_speed_early_error = 0.0;  // its standard error (the fit's scatter)
  double band_speed_lead = 0.0;      // the same of the band's leading edge (BandPath::lead):
                                     // faster than the middle where the band widens (NaN: none)
  double band_speed_lead_error = 0.0;   // its standard error
  int band_turns = 0;                // all turns of the band in the velocity map, at a plate or
                                     // not (a reflection is a turn within turn_travel of a plate)
  double bottom_speed_ratio = 0.0;   // c / V of the strongest bottom front (NaN: none)
  double top_stress_undulation = 0.0;  // amplitude of the top stress at that period, / median
                                       // top stress                                 [-]
  double stress_drop = 0.0;          // 1 - (top stress after the peak) / (peak near first yield)
  double eps_first_yield = 0.0;      // first frame with yield_fraction of particles yielding (NaN)
  double eps_reached = 0.0;          // strain the run reached                       [-]
};

// What the two-sided rule reads of one front (features.cpp), for tools that show it per front
// (compaction-classify --fronts).
struct FrontTiming {
  bool at_onset = false;          // starts within onset_window of the run's first activity
  double first_leg_end_eps = 0.0; // its first turn's strain, else its end          [strain]
  double passes_middle_eps = 0.0; // a front from the top: its first leg passes h0 / 2 (the
                                  // material below it is at rest), else first_leg_end; the
                                  // rule reads it of fronts from the top only      [strain]
};
FrontTiming front_timing(const FrontTracks& tracks, const Front& front,
                         const FeatureSettings& s = {});

// The primary front, whose speed and reflections the features report: the strongest
// propagating front from the top plate, else the strongest propagating front (null: none).
const Front* primary_front(const FrontTracks& t);

// Axes of the run's space-time map (strain of each frame, h0, unit cell).
MapAxes map_axes(const SceneParams& p, const RunResult& r);

// The features from the fronts of the strain-rate map (track_fronts) and the band's path in the
// velocity map (follow_band; an empty path when the run has no velocity map).
Features compute_features(const SceneParams& p, const RunResult& r, const FrontTracks& tracks,
                          const BandPath& band, const FeatureSettings& s = {});

nlohmann::json to_json(const Features& f);

// The features as to_json wrote them (null: NaN; a key that is absent keeps its default), so a
// stored run can be decided again without its bundle. Throws std::invalid_argument naming the
// key whose value has the wrong type.
Features features_from_json(const nlohmann::json& j);

}  // namespace compaction::classify
