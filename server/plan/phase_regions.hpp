// Predicted regions of the phase map: the class the labelled runs predict on a fine grid over
// (log10 S, log10 R) at one phi, with an uncertainty, drawn as the map's background as the
// paper's Fig. 2 does. A pure function of its arguments (docs/dashboard.md, "Predicted
// regions"); GET /api/v1/phase-map/regions serves it.
//
// The rule: a Gaussian-kernel vote of the labelled runs in log space.
//  - Each labelled run i at distance d_i (decades, Euclidean in log10 S and log10 R) from a
//    cell's centre weighs k_i = exp(-d_i^2 / (2 h^2)), h = kBandwidthDecades; runs beyond
//    kCutoffSigmas h are not read.
//  - A run's weight is split between its label and its runner-up by its confidence c (the gap
//    between the classifier's best and runner-up scores): (1 + c) / 2 to the label, (1 - c) / 2
//    to the runner-up (to no class when it has none), as if the two scores were the shares of
//    one. A label with confidence 0.97 votes almost whole; one with 0.05 nearly as much for
//    its runner-up.
//  - A point's replicates vote as one point: each of its k labelled runs with weight k_i / k
//    (Labelled::share), so the vote of a point is its class probabilities (point_tally.hpp),
//    each split by its run's confidence, and four replicates weigh as much as one run.
//  - The cell's class is the one with the largest vote (the first in label order at a tie);
//    its certainty is margin x reach: margin = (best - second) / E and reach =
//    1 - exp(-E / kEvidenceScale), with E = sum k_i the evidence of the cell. Uncertainty is
//    1 - certainty: high where two classes vote alike (a boundary, or low confidences) and
//    where little data is near (reach small). A cell with no run within the cutoff has no
//    class and uncertainty 1.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "plan/adaptive_plan.hpp"

namespace compaction::server::regions {

// The kernel's standard deviation in decades. Sweeps sample the map at 1/8 decade (the adaptive
// default resolution) to 1/2 decade (a 5 x 5 grid over 2 decades of S): h = 1/4 decade lets
// the neighbours of a coarse grid (2 h apart) share a cell between them, while a boundary
// resolved at 1/8 decade stays within a cell or two of its place.
inline constexpr double kBandwidthDecades = 0.25;
// Runs farther than 4 h (one decade; weight e^-8 = 3.4e-4 of a run on the cell) are not read:
// they could not change a class that a nearer run votes for, and the cutoff bounds the work.
inline constexpr double kCutoffSigmas = 4.0;
// The evidence at which reach is 1 - 1/e. A cell on one run has E >= 1 (reach >= 0.993); half
// way across a 1-decade gap, 2 h from a run on each side (E = 2 e^-2 = 0.27), reach is 0.74;
// 3 h from a single run (E = 0.011), 0.05: uncertain, as nothing was measured there.
inline constexpr double kEvidenceScale = 0.2;
// Grid cells per axis: the default, and the range a request may ask for (256 x 256 = 65 536
// cells, about a megabyte of JSON; finer than a screen's pixels of a plot 1 000 px wide would
// not show more).
inline constexpr int kDefaultGrid = 128;
inline constexpr int kMinGrid = 8;
inline constexpr int kMaxGrid = 256;
// Padding of the box beyond the runs' extent on each side (decades): at least the dashboard's
// axis padding (logExtent in web/js/plot.js: max(0.12, 0.04 x span)) for spans up to 6 decades.
inline constexpr double kPadDecades = 0.25;
// The box of an axis whose runs all sit at one value: this many decades wide, centred on it
// (the dashboard's minimum axis span).
inline constexpr double kMinSpanDecades = 1.0;

struct Box {
  double log_S_min = 0, log_S_max = 0;  // decades
  double log_R_min = 0, log_R_max = 0;
};

// The runs' extent in log10 S and log10 R, each axis at least kMinSpanDecades wide, padded by
// kPadDecades; nullopt when there is no point. Points are those of the map (labelled or not),
// so the background covers every marker.
std::optional<Box> box_of(const std::vector<adaptive::Point>& points);

struct Cell {
  std::optional<std::string> cls;  // none: no labelled run within the cutoff
  double uncertainty = 1;          // in [0, 1]
};

struct Regions {
  Box box;
  int grid = 0;                // cells per axis
  std::vector<Cell> cells;     // grid x grid; row j (R, from the bottom) outer, column i (S) inner
  std::size_t runs = 0;        // labelled runs that voted
  const Cell& at(int i, int j) const { return cells[static_cast<std::size_t>(j) * grid + i]; }
  // The centre of cell i (j) in decades.
  double log_S(int i) const;
  double log_R(int j) const;
};

// The predicted class and uncertainty of every cell of a grid x grid division of box, from the
// runs that carry a label (others are ignored). The result depends on the set of runs only, not
// their order, and is the same bits for the same input.
Regions predict(const std::vector<adaptive::Labelled>& runs, const Box& box, int grid);

// The vote at one point (log10 S, log10 R): the cell rule for a single place.
Cell predict_at(const std::vector<adaptive::Labelled>& runs, double log_S, double log_R);

}  // namespace compaction::server::regions
