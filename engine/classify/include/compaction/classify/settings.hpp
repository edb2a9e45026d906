// Every number of the classifier, with its reason (docs/classifier.md).
//
// Lengths are in unit cells (the period of the structure), strain rates in units of the imposed
// mean rate V / h0 (the unit of the space-time map), velocities in units of the plate speed V.
// The decision's soft steps are logistic: at one width from its threshold an evidence is 0.27
// or 0.73, at three widths 0.05 or 0.95.
#pragma once

namespace compaction::classify {

// The front tracker (fronts.hpp) and the band in the velocity map (reflections.hpp).
struct TrackerSettings {
  // Active segments in each frame.
  double rel_threshold = 0.2;   // a row is active above this share of its frame's peak      [-]
  double abs_threshold = 1.0;   // ... and above the imposed mean strain rate V/h0            [V/h0]
  double smooth = 0.125;        // half-width of the box filter over rows                   [cells]
  double merge_gap = 0.5;       // runs of active rows closer than this form one segment    [cells]
  double max_extent = 0.5;      // a segment wider than this share of the current height is
                                // diffuse activity: it is tracked but gives no position    [-]
  // Linking segments into fronts.
  double link_tol = 1.0;        // a segment continues a front within this distance         [cells]
  int velocity_segments = 4;    // a front's velocity, for its predicted interval, is read from
                                // its last this many own segments (three frame steps)      [-]
  int max_missing = 3;          // frames a front may go unseen before it ends              [-]
  // What a front did.
  double plate_zone = 1.5;      // within this distance of a plate a front is "at the plate" [cells]
  double min_travel = 2.0;      // a front propagates when it travels at least this far     [cells]
  double turn_travel = 4.0;     // a turn: the front goes back at least this far            [cells]
  double fit_margin = 1.0;      // the speed fit skips this distance next to either plate   [cells]
  int min_fit_points = 3;       // a speed needs this many edge positions (two always fit)  [-]
  // The band in the row velocity map (reflections.hpp).
  double band_velocity = 0.5;   // the band is where the rows, read from the top down, first
                                // move slower than this share of the plate speed: half way
                                // between moving with the plate (1) and at rest (0)        [V]
  int band_median_frames = 5;   // the band's path is a running median over this many frames
                                // (odd): it removes single-frame flickers of a row near the
                                // threshold                                                 [-]
  double lead_share = 0.1;      // the band's leading edge: where the rows, read from the top
                                // down, first move slower than the material ahead of the band
                                // plus this share of the step from it to the plate speed (the
                                // step's 10 % point; the material ahead carries the elastic
                                // precursor's velocity, up to a quarter of V at R/S = 0.25) [-]
  double early_stage = 0.5;     // the band's early stage: its first leg while the edge is in
                                // the column's upper part, above this share of h0 (before a
                                // band that changes speed on its way has done so)         [h0]
};

// The features (features.hpp).
struct FeatureSettings {
  TrackerSettings tracker;
  double onset_window = 0.05;      // fronts starting this soon after the first activity are
                                   // "at onset"                                     [strain]
  // Struts and the stress peak.
  double yield_fraction = 0.01;    // first yield: this share of particles yields in a frame [-]
  double deflection_floor = 1e-9;  // deflections below this are round-off      [strut thickness]
  int impact_frames = 2;           // first frames left out of stress features (plate impact) [-]
  int peak_frames = 5;             // the stress peak near first yield is looked for up to this
                                   // many frames after it (0.01 of strain at the default frame
                                   // step): the peak of a yielding or buckling structure [frames]
  double drop_window = 0.05;       // the stress after that peak: its median over this much
                                   // strain                                          [strain]
  // Plate stresses during propagation.
  double propagation_start = 0.3;  // plate stresses are read from this share of the primary
                                   // front's first leg on: by then the elastic precursor has
                                   // loaded the bottom                                  [-]
  double bottom_floor = 1e-6;      // the bottom stress counts as at least this share of the top
                                   // stress: an unloaded bottom gives a finite, huge ratio  [-]
  // Undulation of the top stress at one period per row of voids crossed.
  int undulation_min_frames = 8;   // fewer stress samples fit no trend plus harmonic       [-]
  double undulation_periods = 2.0; // the samples must span at least this many periods      [-]
  double undulation_sampling = 4.0;  // ... with at least this many frames per period (twice
                                     // the Nyquist limit)                                 [-]
  double period_min = 0.7;         // the front's speed varies: periods from period_min to
  double period_max = 1.4;         // period_max times the row period are tried, in steps of
  double period_step = 0.05;       // period_step; the best one is kept                   [-]
};

// The decision (classify.hpp): thresholds, the widths of the soft steps around them, and the
// weights of the scores. Each threshold is a physical statement, see docs/classifier.md.
struct DecisionSettings {
  // Thresholds.
  double buckling_growth = 1.0;     // struts buckle: deflection grows > 10x while elastic [decades]
  double buckling_size = 0.01;      // ... and reaches a size that matters: at first yield the
                                    // bending stress of a strut deflected by w is 6 w / t of its
                                    // axial stress, so w / t = 0.01 adds 6 %  [strut thickness]
  double inertial_ratio = 30.0;     // explosive: top stress > 30x bottom stress during propagation [-]
  double coherence = 0.5;           // organised: fronts carry more than half the activity [-]
  double erratic_jump = 2.0;        // erratic: the most active row jumps by more than this
                                    // between frames (a band at c/V = 10 moves 0.7 cell) [cells]
  double reflecting_excess = 0.2;   // a band > 1.2 / (1 - phi) leaves > 1/6 of its porosity and
                                    // must reflect to densify                         [-]
  double slow_band = 0.15;          // a single band from the top slower than (1 - this) / (1 - phi)
                                    // is not a compaction band: it would leave the solid denser
                                    // than solid behind it (mass conservation)         [-]
  double equal_stress = 0.1;        // quasi-static: |log10(top / bottom)| below this  [decades]
  // Widths of the soft steps, each in the unit of its threshold (5 % / 95 % at 3 widths).
  double buckling_width = 0.2;      // growth by 2.5x is elastic, by 40x buckling      [decades]
  double buckling_size_width = 0.16;  // a third of buckling_size (bending 2 %) is no buckling,
                                      // three times it (18 %) is               [decades of w / t]
  double inertial_width = 0.15;     // top / bottom 11 is not explosive, 85 is (class (a) has
                                    // 4-6, (e) ~3000)                                 [decades]
  double erratic_width = 0.3;       // jumps of 1.1 cells are a band moving, 2.9 are not [cells]
  double coherence_width = 0.07;    // fronts carrying 29 % of the activity: not organised,
                                    // 71 %: organised                                   [-]
  double equal_stress_width = 0.03; // top and bottom within 2 % are equal, 55 % apart not [decades]
  double reflecting_width = 0.05;   // 5 % above 1 / (1 - phi) need not reflect, 35 % must [-]
  double slow_band_width = 0.03;    // 24 % below 1 / (1 - phi) is no band, 6 % below is   [-]
  // Weights of the evidence that a band reflects (the strongest one counts).
  double seen_reflection = 0.95;    // a reflection seen before densification; (a) keeps 1 - this
                                    // of its score                                      [-]
  double early_arrival = 0.9;       // the band reaches the far plate before densification: it
                                    // must reflect, though no reflection is seen; (a) keeps
                                    // 1 - this                                          [-]
  // Weights inside the scores of (d) and (e).
  double erratic_base = 0.6;        // (d) with unequal plate stresses keeps this share of its
  double erratic_equal_weight = 0.4;  // score; equal (quasi-static) stresses add this share [-]
  double explosive_off_top = 0.3;   // (e) whose primary front does not start at the top plate,
                                    // the one that drives an explosive front, keeps this share [-]
  double explosive_base = 0.85;     // (e) keeps this share without an undulating top stress; the
  double explosive_undulation_weight = 0.15;  // undulation's share of the variance adds up to
                                              // this (the front crossing rows of voids)   [-]
  double min_score = 0.4;           // below it the run is "unclassified"              [-]
};

struct Settings {
  int min_frames = 5;  // runs with fewer frames (0.01 of strain at the default frame step) are
                       // "unclassified": too short to show a pattern (one window of the band
                       // path's median)                                               [-]
  FeatureSettings features;
  DecisionSettings decision;
};

}  // namespace compaction::classify
