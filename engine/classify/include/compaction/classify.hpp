// Classifier of compaction patterns (a)-(f) of Blatny et al., PRL 128, 228002 (2022).
//
// classify() reads only what a run produced (space-time map, plate stresses, per-frame strut
// diagnostics) and the geometry of its parameters (h0, unit cell, the particles' solid fraction);
// never S or R. It tracks fronts (classify/fronts.hpp), computes features
// (classify/features.hpp) and scores each class with soft rules on physically motivated
// thresholds (docs/classifier.md). The label is the best score; the confidence is its margin
// over the runner-up.
#pragma once

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "compaction/classify/features.hpp"
#include "compaction/classify/fronts.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"

namespace compaction::classify {

// Thresholds of the decision. Each is a physical statement, see docs/classifier.md.
struct DecisionSettings {
  double buckling_growth = 1.0;     // struts buckle: deflection grows > 10x while elastic [decades]
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
  double min_score = 0.4;           // below it the run is "unclassified"              [-]
};

struct Settings {
  FeatureSettings features;
  DecisionSettings decision;
};

struct Classification {
  std::string label;       // "a".."f" or "unclassified"
  double confidence = 0.0; // best score minus runner-up score, in [0, 1]
  std::string runner_up;   // second best class ("" when unclassified)
  std::array<double, 6> scores{};  // a..f, each in [0, 1]
  Features features;
  FrontTracks tracks;
};

// Classifies a finished run. Runs that are not "ok" or have fewer than 5 frames are
// "unclassified" (their features are still computed when there are frames).
Classification classify(const SceneParams& p, const RunResult& r, const Settings& s = {});

// Scores and label from features alone (the decision step).
Classification decide(const Features& f, const DecisionSettings& s = {});

// {class, confidence, runner_up, n_reflections, band_speed_ratio, features{..., scores}}.
// class is "unclassified" when no class fits (summary_json_of() writes null instead).
nlohmann::json to_json(const Classification& c);

// The "classification" object of summary.json: as to_json, with class and runner_up null when
// unclassified (the server accepts only a-f or null).
nlohmann::json summary_json_of(const Classification& c);

}  // namespace compaction::classify
