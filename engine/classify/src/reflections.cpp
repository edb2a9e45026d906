// The band's path through the velocity map and its reflections (reflections.hpp).
#include "compaction/classify/reflections.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "line_fit.hpp"
#include "turns.hpp"

namespace compaction::classify {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The median of x's values, the upper middle of an even count (reorders x; x not empty).
double upper_median(std::vector<double>& x) {
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

// The height of the first row, read from `first` down, slower than `speed` (a share of V): the
// top when the first row is (the band is at the plate), 0 when none is (the band has passed
// every row), NaN when there is no row below the plate zone.
double crossing(const SpaceTimeMap& v, int f, int first, double top, double row, double speed) {
  if (first < 0) return kNaN;
  for (int r = first; r >= 0; --r) {
    if (v.at(f, r) > -speed) return r == first ? top : (r + 0.5) * row;
  }
  return 0.0;
}

// The speed of the material ahead of a band whose middle is at `middle`: the median speed of
// the rows from the bottom plate zone up to a unit cell below the middle (0: no such row).
double speed_ahead(const SpaceTimeMap& v, int f, double middle, double row, double zone,
                   double cell, std::vector<double>& speeds) {
  speeds.clear();
  for (int r = 0; r < v.n_rows && (r + 0.5) * row <= middle - cell; ++r) {
    if ((r + 0.5) * row >= zone) speeds.push_back(-v.at(f, r));
  }
  return speeds.empty() ? 0.0 : upper_median(speeds);
}

// The band's middle and leading edge in each frame (heights / h0): from the plate zone's lower
// edge down (the rows at the plate follow it, or ring with it), the first row slower than
// band_velocity, and the first row slower than the material ahead plus lead_share of the step
// from it to the plate speed.
struct Edges {
  std::vector<double> middle, lead;
};
Edges band_edges(const SpaceTimeMap& v, const MapAxes& axes, const TrackerSettings& s) {
  const double row = v.row_height / axes.h0;
  const double cell = axes.unit_cell / axes.h0;
  const double zone = s.plate_zone * cell;
  Edges e;
  std::vector<double> speeds;
  for (int f = 0; f < v.n_frames; ++f) {
    const double top = 1.0 - axes.eps[f];
    const int first = std::min(v.n_rows - 1, static_cast<int>((top - zone) / row));
    const double middle = crossing(v, f, first, top, row, s.band_velocity);
    e.middle.push_back(middle);
    if (!std::isfinite(middle)) {
      e.lead.push_back(kNaN);
      continue;
    }
    const double ahead = speed_ahead(v, f, middle, row, zone, cell, speeds);
    e.lead.push_back(crossing(v, f, first, top, row, ahead + s.lead_share * (1.0 - ahead)));
  }
  return e;
}

// Running median over `frames` frames (fewer at the ends, NaNs left out; upper_median).
std::vector<double> running_median(const std::vector<double>& x, int frames) {
  const int n = static_cast<int>(x.size()), half = frames / 2;
  std::vector<double> out, window;
  for (int f = 0; f < n; ++f) {
    window.clear();
    for (int g = std::max(0, f - half); g <= std::min(n - 1, f + half); ++g) {
      if (std::isfinite(x[g])) window.push_back(x[g]);
    }
    out.push_back(window.empty() ? kNaN : upper_median(window));
  }
  return out;
}

// An edge's speed over the band's early stage: its heights in the frames before leg_end while
// it is at or above early_stage and fit_margin below the top plate.
EdgeSpeed early_speed(const std::vector<double>& h, const MapAxes& axes, std::size_t leg_end,
                      const TrackerSettings& s) {
  const double margin = s.fit_margin * (axes.unit_cell / axes.h0);
  LineFit fit;
  for (std::size_t f = 0; f < std::min(leg_end, h.size()); ++f) {
    if (std::isfinite(h[f]) && h[f] >= s.early_stage && h[f] <= 1.0 - axes.eps[f] - margin) {
      fit.add(axes.eps[f], h[f]);
    }
  }
  EdgeSpeed e{kNaN, kNaN};
  if (fit.n >= s.min_fit_points && fit.has_slope()) {
    e.speed = -fit.slope();
    e.error = fit.slope_standard_error();
  }
  return e;
}

}  // namespace

BandPath follow_band(const SpaceTimeMap& v, const MapAxes& axes, const TrackerSettings& s) {
  BandPath out;
  out.first_reflection_eps = kNaN;
  out.middle = out.lead = EdgeSpeed{kNaN, kNaN};
  if (v.n_frames == 0 || v.n_frames != static_cast<int>(axes.eps.size())) return out;
  const Edges edges = band_edges(v, axes, s);
  out.height = running_median(edges.middle, s.band_median_frames);
  std::size_t leg_end = out.height.size();  // the first turn's frame, inclusive

  // Turns (turns.hpp): the band sets off from the highest point of its start once it is
  // turn_travel from it.
  const double turn = s.turn_travel * (axes.unit_cell / axes.h0);
  TurnFollower follower(turn);
  double start = out.height.front();
  for (int f = 1; f < v.n_frames; ++f) {
    const double h = out.height[f];
    if (!std::isfinite(h)) continue;
    if (!follower.moving()) {
      if (std::abs(h - start) >= turn) follower.set_off(h > start ? 1 : -1, f, h);
      else if (h > start) start = h;
      continue;
    }
    const std::optional<Turn> t = follower.next(f, h);
    if (!t) continue;
    // At a plate: nearer to it than the distance it goes back (behind a band the material is
    // only partly compacted and slower than the plate, so the crossing stops short of it).
    const bool at_plate = t->came < 0 ? t->at <= turn : t->at >= 1.0 - axes.eps[t->index] - turn;
    if (out.n_turns == 0) leg_end = t->index + 1;
    ++out.n_turns;
    if (at_plate) {
      if (out.n_reflections == 0) out.first_reflection_eps = axes.eps[t->index];
      ++out.n_reflections;
    }
  }
  out.middle = early_speed(out.height, axes, leg_end, s);
  out.lead = early_speed(running_median(edges.lead, s.band_median_frames), axes, leg_end, s);
  return out;
}

}  // namespace compaction::classify
