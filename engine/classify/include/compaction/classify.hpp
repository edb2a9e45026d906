// Classifier of compaction patterns (a)-(f) of Blatny et al., PRL 128, 228002 (2022).
//
// classify() reads only what a run produced (space-time map, plate stresses, per-frame strut
// diagnostics) and the geometry of its parameters (h0, unit cell, the particles' solid fraction);
// never S or R. It tracks the fronts of the strain-rate map (classify/fronts.hpp), follows the
// band through the velocity map (classify/reflections.hpp), computes features
// (classify/features.hpp) and decides: it scores each class with soft rules on physically
// motivated thresholds (docs/classifier.md). The label is the best score; the confidence is its
// margin over the runner-up. Every threshold is in classify/settings.hpp.
#pragma once

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "compaction/classify/features.hpp"
#include "compaction/classify/fronts.hpp"
#include "compaction/classify/reflections.hpp"
#include "compaction/classify/settings.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"

namespace compaction::classify {

struct Classification {
  std::string label;       // "a".."f" or "unclassified"
  double confidence = 0.0; // best score minus runner-up score, in [0, 1]
  std::string runner_up;   // second best class ("" when unclassified)
  std::array<double, 6> scores{};  // a..f, each in [0, 1]
  Features features;
  FrontTracks tracks;
};

// Classifies a finished run: track_fronts, follow_band, compute_features, decide. Runs with fewer
// than s.min_frames frames, or a map whose frames are not the run's, are "unclassified" without
// features; runs that are not "ok" are
// "unclassified" with their features.
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
