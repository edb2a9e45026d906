// The band's path through the velocity map and its reflections (reflections.hpp).
#include "compaction/classify/reflections.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace compaction::classify {

BandPath follow_band(const SpaceTimeMap& v, const MapAxes& axes, const TrackerSettings& s) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  BandPath out;
  out.first_reflection_eps = kNaN;
  if (v.n_frames == 0 || v.n_frames != static_cast<int>(axes.eps.size())) return out;
  const double row = v.row_height / axes.h0;
  const double cell = axes.unit_cell / axes.h0;
  const double zone = s.plate_zone * cell, turn = s.turn_travel * cell;

  std::vector<double> raw;
  for (int f = 0; f < v.n_frames; ++f) {
    const double top = 1.0 - axes.eps[f];
    // From the plate zone's lower edge down (the rows at the plate follow it, or ring with
    // it): the first row slower than half the plate speed. At rest there: the band is at the
    // plate; moving all the way down: at the bottom.
    const int first = std::min(v.n_rows - 1, static_cast<int>((top - zone) / row));
    double h = first >= 0 ? 0.0 : kNaN;
    for (int r = first; r >= 0; --r) {
      if (v.at(f, r) > -0.5f) { h = r == first ? top : (r + 0.5) * row; break; }
    }
    raw.push_back(h);
  }
  // A median over five frames removes single-frame flickers of a row near the threshold.
  for (int f = 0; f < v.n_frames; ++f) {
    std::array<double, 5> w{};
    int n = 0;
    for (int g = std::max(0, f - 2); g <= std::min(v.n_frames - 1, f + 2); ++g) {
      if (!std::isfinite(raw[g])) continue;
      int i = n++;  // insertion sort
      for (; i > 0 && w[i - 1] > raw[g]; --i) w[i] = w[i - 1];
      w[i] = raw[g];
    }
    out.height.push_back(n ? w[n / 2] : kNaN);
  }

  // Reversals with hysteresis, each at its extreme (as the front tracker's turns).
  int dir = 0;
  double ext = out.height.front();
  int ext_f = 0;
  for (int f = 1; f < v.n_frames; ++f) {
    const double h = out.height[f];
    if (!std::isfinite(h)) continue;
    if (dir == 0) {
      if (std::abs(h - ext) >= turn) dir = h > ext ? 1 : -1;
      else if (h > ext) ext = h, ext_f = f;  // the start: the highest point before it moves
      if (dir != 0) ext = h, ext_f = f;
      continue;
    }
    if ((dir < 0 && h < ext) || (dir > 0 && h > ext)) { ext = h, ext_f = f; continue; }
    if (std::abs(h - ext) < turn) continue;
    // At a plate: nearer to it than the distance it goes back (behind a band the material is
    // only partly compacted and slower than the plate, so the crossing stops short of it).
    const bool at_plate = dir < 0 ? ext <= turn : ext >= 1.0 - axes.eps[ext_f] - turn;
    ++out.n_turns;
    if (at_plate) {
      if (out.n_reflections == 0) out.first_reflection_eps = axes.eps[ext_f];
      ++out.n_reflections;
    }
    dir = -dir;
    ext = h, ext_f = f;
  }
  return out;
}

}  // namespace compaction::classify
