// Features of a run: fronts, plate stresses, strut deflections.
#include "compaction/classify/features.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

namespace compaction::classify {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The primary front: the strongest propagating front from the top plate, else the strongest
// propagating front.
const Front* primary_front(const FrontTracks& t) {
  const Front* best = nullptr;
  for (int pass = 0; pass < 2 && !best; ++pass) {
    for (const auto& fr : t.fronts) {
      if (!fr.propagating || (pass == 0 && fr.origin != Origin::top)) continue;
      if (!best || fr.mass() > best->mass()) best = &fr;
    }
  }
  return best;
}

// Strain at which a front leaves its first direction (its first turn, else its end).
double first_leg_end(const Front& fr) {
  return fr.turns.empty() ? fr.end_eps() : fr.turns.front().eps;
}

// Amplitude of y at period P (least squares on cos/sin after removing a linear trend).
struct Harmonic { double amplitude = 0.0, share = 0.0; };
Harmonic harmonic(const std::vector<double>& x, const std::vector<double>& y, double period) {
  const std::size_t n = x.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) { sx += x[i]; sy += y[i]; sxx += x[i] * x[i]; sxy += x[i] * y[i]; }
  const double den = n * sxx - sx * sx;
  const double b = den > 0 ? (n * sxy - sx * sy) / den : 0.0, a = (sy - b * sx) / n;
  double cc = 0, ss = 0, cs = 0, yc = 0, ys = 0, var = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - a - b * x[i], w = 2.0 * M_PI * x[i] / period;
    const double c = std::cos(w), s = std::sin(w);
    cc += c * c; ss += s * s; cs += c * s; yc += r * c; ys += r * s; var += r * r;
  }
  const double det = cc * ss - cs * cs;
  Harmonic h;
  if (!(det > 0) || !(var > 0)) return h;
  const double ac = (yc * ss - ys * cs) / det, as = (ys * cc - yc * cs) / det;
  h.amplitude = std::hypot(ac, as);
  h.share = std::min(1.0, (ac * yc + as * ys) / var);  // explained share of the variance
  return h;
}

}  // namespace

MapAxes map_axes(const SceneParams& p, const RunResult& r) {
  MapAxes a;
  a.h0 = p.h0;
  a.unit_cell = p.unit_cell();
  a.eps.reserve(r.frames.size());
  for (const auto& f : r.frames) a.eps.push_back(f.eps);
  return a;
}

Features compute_features(const SceneParams& p, const RunResult& r, const FrontTracks& t,
                          const FeatureSettings& s) {
  Features F;
  F.eps_reached = r.eps_reached;
  const double phi = r.phi_discrete > 0 ? r.phi_discrete : p.phi;
  F.nonreflecting_speed = 1.0 / (1.0 - phi);
  const double cell = p.unit_cell() / p.h0;
  const double zone = s.tracker.plate_zone * cell;

  // Fronts at onset and the primary front.
  double first_activity = kNaN;
  for (const auto& segs : t.segments) {
    if (!segs.empty()) { first_activity = segs.front().eps; break; }
  }
  // A front that starts within onset_window of the first activity (false when there is none).
  auto at_onset = [&](const Front& fr) {
    return fr.start_eps() <= first_activity + s.onset_window;
  };
  double bottom_mass = 0.0;
  const Front* bottom = nullptr;
  for (const auto& fr : t.fronts) {
    if (!fr.propagating) continue;
    ++F.n_fronts;
    if (fr.origin == Origin::top) F.top_front = true;
    if (fr.origin == Origin::bottom) {
      F.bottom_front = true;
      if (fr.mass() > bottom_mass) { bottom_mass = fr.mass(); bottom = &fr; }
    }
    if (at_onset(fr)) {
      ++F.n_fronts_onset;
      F.onset_origins.push_back(to_string(fr.origin));
    }
  }
  F.bottom_speed_ratio = bottom ? bottom->speed : kNaN;
  // Two-sided (class (c)): bands emerge from both ends. The one from the top starts at the
  // onset; one from the bottom that starts after that band's first leg is over is a late event
  // (near densification, or a reflected band), not a second band emerging.
  for (const auto& a : t.fronts) {
    if (!a.propagating || a.origin != Origin::top || !at_onset(a)) continue;
    for (const auto& b : t.fronts) {
      if (!b.propagating || b.origin != Origin::bottom) continue;
      if (b.start_eps() < first_leg_end(a) && a.start_eps() < first_leg_end(b)) F.two_sided = true;
    }
  }
  // Coherence: the share of all segment activity that some propagating front contains (each
  // segment counted once, also when crossing fronts share it).
  {
    std::set<std::pair<int, double>> in_front;
    for (const auto& fr : t.fronts) {
      if (!fr.propagating) continue;
      for (const auto& g : fr.path) in_front.insert({g.frame, g.lo});
    }
    double m = 0.0;
    for (const auto& segs : t.segments) {
      for (const auto& g : segs) if (in_front.count({g.frame, g.lo})) m += g.mass;
    }
    F.coherence = t.total_mass > 0 ? m / t.total_mass : kNaN;
  }

  const Front* prim = primary_front(t);
  F.band_speed_ratio = prim ? prim->speed : kNaN;
  F.n_reflections = prim ? prim->n_reflections : 0;
  F.first_reflection_eps = kNaN;
  if (prim && !prim->turns.empty() && prim->turns.front().where != Origin::interior) {
    F.first_reflection_eps = prim->turns.front().eps;
  }
  if (r.velocity.n_frames == r.spacetime.n_frames && r.velocity.n_frames > 0) {
    // The velocity map sees reflections the strain-rate map hides (reflections.hpp).
    const BandPath band = follow_band(r.velocity, map_axes(p, r), s.tracker);
    F.band_turns = band.n_turns;
    if (band.n_reflections > F.n_reflections) {
      F.n_reflections = band.n_reflections;
      F.first_reflection_eps = band.first_reflection_eps;
    }
  }
  F.primary_origin = prim ? to_string(prim->origin) : "";
  F.speed_excess = F.band_speed_ratio / F.nonreflecting_speed - 1.0;
  F.arrival_eps = kNaN;
  if (prim) {
    for (const auto& g : prim->path) {
      const bool there = prim->origin == Origin::bottom ? g.hi >= 1.0 - g.eps - zone : g.lo <= zone;
      if (there) { F.arrival_eps = g.eps; break; }
    }
  }

  // Jumps of the most active row between consecutive frames with activity.
  {
    std::vector<double> jumps;
    int prev = -1;
    const auto& m = r.spacetime;
    for (int f = 0; f < m.n_frames; ++f) {
      int arg = -1;
      float best = static_cast<float>(s.tracker.abs_threshold);
      for (int q = 0; q < m.n_rows; ++q) {
        if (m.at(f, q) > best) { best = m.at(f, q); arg = q; }
      }
      if (arg >= 0 && prev >= 0) jumps.push_back(std::abs(arg - prev) * m.row_height / p.unit_cell());
      if (arg >= 0) prev = arg;
    }
    F.peak_jump = median(jumps);
  }

  // First yield and strut deflection before it.
  const auto& fr = r.frames;
  int fy = -1;
  for (std::size_t i = 0; i < fr.size(); ++i) {
    if (fr[i].plastic_fraction >= s.yield_fraction) { fy = static_cast<int>(i); break; }
  }
  F.eps_first_yield = fy >= 0 ? fr[fy].eps : kNaN;
  if (fy > 0) {
    const double before = std::max(fr[fy - 1].max_deflection, s.deflection_floor);
    const double base = std::max(fr[0].max_deflection, s.deflection_floor);
    F.deflection_before_yield = fr[fy - 1].max_deflection;
    F.deflection_growth = std::log10(before / base);
  }

  // Stress peak near first yield, then drop: peak of the top stress up to a few frames after
  // first yield (past the impact frames), against the median of the following 0.05 of strain.
  if (fy >= 0) {
    int ipk = -1;
    const int stop = std::min<int>(fy + 5, static_cast<int>(fr.size()) - 1);
    for (int i = s.impact_frames; i <= stop; ++i) {
      if (ipk < 0 || fr[i].sigma_top > fr[ipk].sigma_top) ipk = i;
    }
    if (ipk >= 0 && fr[ipk].sigma_top > 0) {
      std::vector<double> after;
      for (std::size_t i = ipk + 1; i < fr.size() && fr[i].eps <= fr[ipk].eps + 0.05; ++i) {
        after.push_back(fr[i].sigma_top);
      }
      if (!after.empty()) F.stress_drop = 1.0 - median(after) / fr[ipk].sigma_top;
    }
  }

  // Plate stresses during propagation: from 30 % of the primary front's first leg (the elastic
  // precursor has had time to load the bottom) to its end; the whole run if there is no front.
  const double leg_end = prim ? first_leg_end(*prim) : r.eps_reached;
  std::vector<double> xs, tops, bots;
  for (std::size_t i = s.impact_frames; i < fr.size(); ++i) {
    if (fr[i].eps < 0.3 * leg_end || fr[i].eps > leg_end) continue;
    xs.push_back(fr[i].eps);
    tops.push_back(fr[i].sigma_top);
    bots.push_back(std::abs(fr[i].sigma_bottom));
  }
  const double mt = median(tops), mb = median(bots);
  F.stress_ratio = std::isfinite(mt) ? mt / std::max(mb, 1e-6 * std::abs(mt)) : kNaN;

  // Undulation of the top stress at one period per row of voids the front crosses,
  // P = (L / h0) / (c_b / V); the best of periods 0.7-1.4 P (the front's speed varies).
  if (std::isfinite(F.band_speed_ratio) && F.band_speed_ratio > 0 && mt > 0 && xs.size() >= 8) {
    const double P = cell / F.band_speed_ratio;
    const double span = xs.back() - xs.front(), d = xs.size() > 1 ? span / (xs.size() - 1) : 0;
    if (span >= 2 * P && P >= 4 * d) {
      for (double q = 0.7; q <= 1.4001; q += 0.05) {
        const Harmonic h = harmonic(xs, tops, q * P);
        if (h.share > F.undulation_share) {
          F.undulation_share = h.share;
          F.top_stress_undulation = h.amplitude / mt;
        }
      }
    }
  }
  return F;
}

nlohmann::json to_json(const Features& f) {
  auto num = [](double v) -> nlohmann::json { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {
      {"n_fronts", f.n_fronts},
      {"n_fronts_onset", f.n_fronts_onset},
      {"onset_origins", f.onset_origins},
      {"top_front", f.top_front},
      {"bottom_front", f.bottom_front},
      {"two_sided", f.two_sided},
      {"primary_origin", f.primary_origin},
      {"n_reflections", f.n_reflections},
      {"first_reflection_eps", num(f.first_reflection_eps)},
      {"band_turns", f.band_turns},
      {"band_speed_ratio", num(f.band_speed_ratio)},
      {"bottom_speed_ratio", num(f.bottom_speed_ratio)},
      {"nonreflecting_speed", num(f.nonreflecting_speed)},
      {"speed_excess", num(f.speed_excess)},
      {"arrival_eps", num(f.arrival_eps)},
      {"coherence", num(f.coherence)},
      {"peak_jump", num(f.peak_jump)},
      {"stress_ratio", num(f.stress_ratio)},
      {"top_stress_undulation", num(f.top_stress_undulation)},
      {"undulation_share", num(f.undulation_share)},
      {"stress_drop", num(f.stress_drop)},
      {"eps_first_yield", num(f.eps_first_yield)},
      {"deflection_before_yield", num(f.deflection_before_yield)},
      {"deflection_growth", num(f.deflection_growth)},
      {"eps_reached", num(f.eps_reached)},
  };
}

}  // namespace compaction::classify
