// The decision: soft rules on the features, one score per class.
#include <algorithm>
#include <cmath>
#include <limits>

#include "compaction/classify.hpp"

namespace compaction::classify {

namespace {

// Logistic step from 0 to 1 around x0 with width w; `missing` when x is NaN (no feature).
double logistic(double x, double x0, double w, double missing) {
  if (!std::isfinite(x)) return missing;
  return 1.0 / (1.0 + std::exp(-(x - x0) / w));
}

// What an evidence is when its feature is missing.
constexpr double kAbsent = 0.0;     // the evidence does not hold
constexpr double kPresent = 1.0;    // it holds
constexpr double kUndecided = 0.5;  // neither

constexpr const char* kNames[6] = {"a", "b", "c", "d", "e", "f"};

}  // namespace

Classification decide(const Features& F, const DecisionSettings& s) {
  Classification c;
  c.features = F;
  const double log_ratio = std::isfinite(F.stress_ratio) && F.stress_ratio > 0
                               ? std::log10(F.stress_ratio) : std::numeric_limits<double>::quiet_NaN();
  // Elementary evidence, each in [0, 1].
  // Struts buckle when their deflection grows while they are elastic and reaches a size that
  // shapes how they yield; growth alone, from round-off to a hundredth of a thickness, is not
  // buckling (no deflection, log10 of 0, is none).
  const double log_deflection = F.deflection_before_yield > 0
                                    ? std::log10(F.deflection_before_yield)
                                    : -std::numeric_limits<double>::infinity();
  const double buckled =
      logistic(F.deflection_growth, s.buckling_growth, s.buckling_width, kAbsent) *
      logistic(log_deflection, std::log10(s.buckling_size), s.buckling_size_width, kAbsent);
  const double inertial =
      logistic(log_ratio, std::log10(s.inertial_ratio), s.inertial_width, kAbsent);
  // Organised: fronts carry the activity, and the most active row moves by less than a band
  // could travel in a frame (erratic activity jumps between random rows). Without activity a
  // run is neither organised enough for (a)-(c) nor disorganised enough for (d).
  const double erratic = logistic(F.peak_jump, s.erratic_jump, s.erratic_width, kAbsent);
  const double coherent =
      logistic(F.coherence, s.coherence, s.coherence_width, kAbsent) * (1.0 - erratic);
  const double organised =
      logistic(F.coherence, s.coherence, s.coherence_width, kPresent) * (1.0 - erratic);
  const double equal =
      1.0 - logistic(std::abs(log_ratio), s.equal_stress, s.equal_stress_width, kPresent);
  const bool from_top = F.primary_origin == "top";
  const double single = from_top && !F.two_sided ? 1.0 : 0.0;
  // A band reflects when it is seen to reflect, or when it must: it runs faster than the
  // non-reflecting band (1 / (1 - phi)), or reaches the far plate before the sample is dense,
  // leaving pores open behind it (mass conservation, c_b / V = 1 / (1 - phi / phi_f)).
  const double fast = logistic(F.speed_excess, s.reflecting_excess, s.reflecting_width, kUndecided);
  // Both the arrival and a seen reflection count when they come before the strain at which a
  // band within the tolerance would have densified the sample, (1 - phi) / (1 + excess): later
  // the last open pores close (the reflection of a band that was only slightly too fast).
  const double dense_eps = (1.0 / F.nonreflecting_speed) / (1.0 + s.reflecting_excess);
  const double early =
      std::isfinite(F.arrival_eps) && F.arrival_eps < dense_eps ? s.early_arrival : 0.0;
  const double seen = F.n_reflections >= 1 && std::isfinite(F.first_reflection_eps) &&
                              F.first_reflection_eps < dense_eps
                          ? s.seen_reflection : 0.0;
  const double reflecting = std::max({seen, fast, early});
  // Mass conservation also bounds a band from below: c_b / V >= 1 / (1 - phi) (phi_f <= 1). A
  // single front from the top that is clearly slower is activity drifting down row by row, not
  // a band compacting everything it passes (erratic compaction, class (d), can look like that).
  const double banded = logistic(F.speed_excess, -s.slow_band, s.slow_band_width, kPresent);
  const double elastic_struts = 1.0 - buckled;
  const double not_inertial = 1.0 - inertial;

  auto& S = c.scores;
  S[0] = elastic_struts * not_inertial * coherent * single * banded * (1.0 - reflecting);
  S[1] = elastic_struts * not_inertial * coherent * single * banded * reflecting;
  S[2] = elastic_struts * not_inertial * coherent * (F.two_sided ? 1.0 : 0.0);
  S[3] = elastic_struts * not_inertial * (1.0 - organised * (single > 0.0 ? banded : 1.0)) *
         (s.erratic_base + s.erratic_equal_weight * equal);
  S[4] = elastic_struts * inertial * (from_top ? 1.0 : s.explosive_off_top) *
         (s.explosive_base + s.explosive_undulation_weight * F.undulation_share);
  S[5] = buckled;

  int best = 0, second = -1;
  for (int i = 1; i < 6; ++i) if (S[i] > S[best]) best = i;
  for (int i = 0; i < 6; ++i) if (i != best && (second < 0 || S[i] > S[second])) second = i;
  if (S[best] < s.min_score) {
    c.label = "unclassified";
    c.confidence = 0.0;
    c.runner_up = kNames[best];
    return c;
  }
  c.label = kNames[best];
  c.runner_up = kNames[second];
  c.confidence = std::clamp(S[best] - S[second], 0.0, 1.0);
  return c;
}

Classification classify(const SceneParams& p, const RunResult& r, const Settings& s) {
  if (static_cast<int>(r.frames.size()) < s.min_frames ||
      r.spacetime.n_frames != static_cast<int>(r.frames.size())) {
    Classification c;
    c.label = "unclassified";
    return c;
  }
  const MapAxes axes = map_axes(p, r);
  FrontTracks tracks = track_fronts(r.spacetime, axes, s.features.tracker);
  const BandPath band = follow_band(r.velocity, axes, s.features.tracker);
  const Features F = compute_features(p, r, tracks, band, s.features);
  Classification c = decide(F, s.decision);
  c.tracks = std::move(tracks);
  if (r.status != RunStatus::ok) {
    c.label = "unclassified";
    c.confidence = 0.0;
  }
  return c;
}

nlohmann::json to_json(const Classification& c) {
  nlohmann::json feats = to_json(c.features);
  nlohmann::json scores = nlohmann::json::object();
  for (int i = 0; i < 6; ++i) scores[kNames[i]] = c.scores[i];
  feats["scores"] = scores;
  const double v = c.features.band_speed_ratio;
  return {{"class", c.label},
          {"confidence", c.confidence},
          {"runner_up", c.runner_up.empty() ? nlohmann::json() : nlohmann::json(c.runner_up)},
          {"n_reflections", c.features.n_reflections},
          {"band_speed_ratio", std::isfinite(v) ? nlohmann::json(v) : nlohmann::json()},
          {"features", feats}};
}

nlohmann::json summary_json_of(const Classification& c) {
  nlohmann::json j = to_json(c);
  if (c.label == "unclassified") {
    j["class"] = nullptr;
    j["features"]["label"] = "unclassified";
  }
  return j;
}

}  // namespace compaction::classify
