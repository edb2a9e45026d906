// The band's path through the velocity map and its reflections (reflections.hpp).
#include "compaction/classify/reflections.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "turns.hpp"

namespace compaction::classify {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The band's height in each frame: from the plate zone's lower edge down (the rows at the plate
// follow it, or ring with it), the first row slower than band_velocity. At rest there: the band
// is at the plate; moving all the way down: at the bottom. NaN: no row below the plate zone.
std::vector<double> band_heights(const SpaceTimeMap& v, const MapAxes& axes,
                                 const TrackerSettings& s) {
  const double row = v.row_height / axes.h0;
  const double zone = s.plate_zone * (axes.unit_cell / axes.h0);
  std::vector<double> heights;
  for (int f = 0; f < v.n_frames; ++f) {
    const double top = 1.0 - axes.eps[f];
    const int first = std::min(v.n_rows - 1, static_cast<int>((top - zone) / row));
    double h = first >= 0 ? 0.0 : kNaN;
    for (int r = first; r >= 0; --r) {
      if (v.at(f, r) > -s.band_velocity) { h = r == first ? top : (r + 0.5) * row; break; }
    }
    heights.push_back(h);
  }
  return heights;
}

// Running median over `frames` frames (fewer at the ends, NaNs left out; the upper middle of an
// even count).
std::vector<double> running_median(const std::vector<double>& x, int frames) {
  const int n = static_cast<int>(x.size()), half = frames / 2;
  std::vector<double> out, window;
  for (int f = 0; f < n; ++f) {
    window.clear();
    for (int g = std::max(0, f - half); g <= std::min(n - 1, f + half); ++g) {
      if (std::isfinite(x[g])) window.push_back(x[g]);
    }
    std::sort(window.begin(), window.end());
    out.push_back(window.empty() ? kNaN : window[window.size() / 2]);
  }
  return out;
}

}  // namespace

BandPath follow_band(const SpaceTimeMap& v, const MapAxes& axes, const TrackerSettings& s) {
  BandPath out;
  out.first_reflection_eps = kNaN;
  if (v.n_frames == 0 || v.n_frames != static_cast<int>(axes.eps.size())) return out;
  out.height = running_median(band_heights(v, axes, s), s.band_median_frames);

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
    ++out.n_turns;
    if (at_plate) {
      if (out.n_reflections == 0) out.first_reflection_eps = axes.eps[t->index];
      ++out.n_reflections;
    }
  }
  return out;
}

}  // namespace compaction::classify
