// Features of a run: fronts, plate stresses, strut deflections.
#include "compaction/classify/features.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "line_fit.hpp"

namespace compaction::classify {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Strain at which a front leaves its first direction (its first turn, else its end).
double first_leg_end(const Front& fr) {
  return fr.turns.empty() ? fr.end_eps() : fr.turns.front().eps;
}

// Strain at which a front from the top passes the middle of the sample on its first leg, else
// the end of that leg. The material below a band from the top is at rest, so its middle is at
// half the initial height, h0 / 2.
double passes_middle(const Front& fr) {
  const std::size_t leg =
      fr.turns.empty() ? fr.path.size() : static_cast<std::size_t>(fr.turns.front().index) + 1;
  for (std::size_t i = 0; i < leg && i < fr.path.size(); ++i) {
    if (fr.path[i].centroid < 0.5) return fr.path[i].eps;
  }
  return first_leg_end(fr);
}

// Amplitude of y at period P (least squares on cos/sin after removing a linear trend).
struct Harmonic { double amplitude = 0.0, share = 0.0; };
Harmonic harmonic(const std::vector<double>& x, const std::vector<double>& y, double period) {
  const std::size_t n = x.size();
  LineFit trend;
  for (std::size_t i = 0; i < n; ++i) trend.add(x[i], y[i]);
  const double b = trend.has_slope() ? trend.slope() : 0.0, a = trend.intercept(b);
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

// Strain of the first active segment (NaN: no activity).
double first_activity(const FrontTracks& t) {
  for (const auto& segs : t.segments) {
    if (!segs.empty()) return segs.front().eps;
  }
  return kNaN;
}

// A front that starts within onset_window of the first activity (false when there is none).
bool at_onset(const Front& fr, double first_activity_eps, const FeatureSettings& s) {
  return fr.start_eps() <= first_activity_eps + s.onset_window;
}

// Counts of the propagating fronts, where they start, the bottom front's speed, and whether
// the run is two-sided.
void front_counts(const FrontTracks& t, const FeatureSettings& s, Features& F) {
  const double onset = first_activity(t);
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
    if (at_onset(fr, onset, s)) {
      ++F.n_fronts_onset;
      F.onset_origins.push_back(to_string(fr.origin));
    }
  }
  F.bottom_speed_ratio = bottom ? bottom->speed : kNaN;
  // Two-sided (class (c)): bands emerge from both ends and cross inside the sample. The one
  // from the top starts at the onset; one from the bottom must start before that band has passed
  // the middle. A bottom front that starts later is the lowest rows yielding as the top band
  // nears the bottom plate (it meets the band in the lower half), near densification, or a
  // reflected band: not a second band emerging.
  for (const auto& a : t.fronts) {
    if (!a.propagating || a.origin != Origin::top || !at_onset(a, onset, s)) continue;
    for (const auto& b : t.fronts) {
      if (!b.propagating || b.origin != Origin::bottom) continue;
      if (b.start_eps() < passes_middle(a) && a.start_eps() < first_leg_end(b)) F.two_sided = true;
    }
  }
}

// The share of all segment activity that some propagating front contains (each segment
// counted once, also when crossing fronts share it); NaN without activity.
double coherence(const FrontTracks& t) {
  std::set<std::pair<int, double>> in_front;
  for (const auto& fr : t.fronts) {
    if (!fr.propagating) continue;
    for (const auto& g : fr.path) in_front.insert({g.frame, g.lo});
  }
  double m = 0.0;
  for (const auto& segs : t.segments) {
    for (const auto& g : segs) if (in_front.count({g.frame, g.lo})) m += g.mass;
  }
  return t.total_mass > 0 ? m / t.total_mass : kNaN;
}

// The primary front's speed, origin and arrival at the far plate, and the reflections: of the
// band in the velocity map when it sees more of them than the primary front's turns (it sees
// reflections the strain-rate map hides, reflections.hpp).
void band_features(const Front* prim, const BandPath& band, double zone, Features& F) {
  F.band_speed_ratio = prim ? prim->speed : kNaN;
  F.band_speed_error = prim ? prim->speed_error : kNaN;
  F.band_speed_transit = prim ? prim->transit_speed : kNaN;
  F.band_speed_transit_error = prim ? prim->transit_error : kNaN;
  F.n_reflections = prim ? prim->n_reflections : 0;
  F.first_reflection_eps = kNaN;
  if (prim && !prim->turns.empty() && prim->turns.front().where != Origin::interior) {
    F.first_reflection_eps = prim->turns.front().eps;
  }
  F.band_turns = band.n_turns;
  F.band_speed_early = band.middle.speed;
  F.band_speed_early_error = band.middle.error;
  F.band_speed_lead = band.lead.speed;
  F.band_speed_lead_error = band.lead.error;
  if (band.n_reflections > F.n_reflections) {
    F.n_reflections = band.n_reflections;
    F.first_reflection_eps = band.first_reflection_eps;
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
}

// Median jump of the most active row (above abs_threshold) between consecutive frames with
// activity, in unit cells; NaN with fewer than two such frames.
double peak_jump(const SpaceTimeMap& m, double unit_cell, double abs_threshold) {
  std::vector<double> jumps;
  int prev = -1;
  for (int f = 0; f < m.n_frames; ++f) {
    int arg = -1;
    float best = static_cast<float>(abs_threshold);
    for (int q = 0; q < m.n_rows; ++q) {
      if (m.at(f, q) > best) { best = m.at(f, q); arg = q; }
    }
    if (arg >= 0 && prev >= 0) jumps.push_back(std::abs(arg - prev) * m.row_height / unit_cell);
    if (arg >= 0) prev = arg;
  }
  return median(jumps);
}

// The largest strut deflection when the plastic fraction reaches yield_fraction, between the
// last elastic frame fy - 1 and the yield frame fy. An elastic instability grows by decades
// within a frame (1.6 decades per 0.002 of strain in example (f) at 8 cells across a strut), so
// the last elastic frame can read far below the deflection with which the struts yield. The
// deflection is carried on from that frame at its own growth rate over the frame before it, up
// to the strain where the plastic fraction (linear between the frames) reaches yield_fraction,
// and never beyond the yield frame's deflection. A deflection that was not growing stays as the
// last elastic frame has it, and one growing slowly from round-off stays near it.
double deflection_at_yield(const std::vector<Frame>& fr, int fy, const FeatureSettings& s) {
  const Frame& last = fr[fy - 1];
  if (fy < 2 || !(last.max_deflection > s.deflection_floor)) return last.max_deflection;
  const Frame& prev = fr[fy - 2];
  const Frame& yield = fr[fy];
  const double rate = std::log10(last.max_deflection /
                                 std::max(prev.max_deflection, s.deflection_floor)) /
                      (last.eps - prev.eps);  // decades per unit strain
  if (!(rate > 0) || !(yield.eps > last.eps)) return last.max_deflection;
  const double rise = yield.plastic_fraction - last.plastic_fraction;
  const double share =
      rise > 0 ? std::clamp((s.yield_fraction - last.plastic_fraction) / rise, 0.0, 1.0) : 1.0;
  const double carried =
      last.max_deflection * std::pow(10.0, rate * share * (yield.eps - last.eps));
  return std::max(last.max_deflection, std::min(carried, yield.max_deflection));
}

// First yield and the growth of the strut deflection before it; returns the frame of first
// yield (-1: none).
int strut_features(const std::vector<Frame>& fr, const FeatureSettings& s, Features& F) {
  int fy = -1;
  for (std::size_t i = 0; i < fr.size(); ++i) {
    if (fr[i].plastic_fraction >= s.yield_fraction) { fy = static_cast<int>(i); break; }
  }
  F.eps_first_yield = fy >= 0 ? fr[fy].eps : kNaN;
  if (fy > 0) {
    const double before = std::max(fr[fy - 1].max_deflection, s.deflection_floor);
    const double base = std::max(fr[0].max_deflection, s.deflection_floor);
    F.deflection_before_yield = deflection_at_yield(fr, fy, s);
    F.deflection_growth = std::log10(before / base);
  }
  return fy;
}

// The drop of the top stress after its peak near first yield (frame fy): the peak up to
// peak_frames after fy (past the impact frames), against the median of the following
// drop_window of strain. 0 when there is no peak or nothing after it.
double stress_drop(const std::vector<Frame>& fr, int fy, const FeatureSettings& s) {
  int ipk = -1;
  const int stop = std::min<int>(fy + s.peak_frames, static_cast<int>(fr.size()) - 1);
  for (int i = s.impact_frames; i <= stop; ++i) {
    if (ipk < 0 || fr[i].sigma_top > fr[ipk].sigma_top) ipk = i;
  }
  if (ipk < 0 || !(fr[ipk].sigma_top > 0)) return 0.0;
  std::vector<double> after;
  for (std::size_t i = ipk + 1; i < fr.size() && fr[i].eps <= fr[ipk].eps + s.drop_window; ++i) {
    after.push_back(fr[i].sigma_top);
  }
  return after.empty() ? 0.0 : 1.0 - median(after) / fr[ipk].sigma_top;
}

// Plate stresses while the primary front runs, from propagation_start of its first leg (the
// elastic precursor has had time to load the bottom) to the leg's end: the ratio of the median
// top and bottom stresses, and the undulation of the top stress at one period per row of
// voids the front crosses, P = (L / h0) / (c_b / V), the best of period_min-period_max times P
// (the front's speed varies).
void stress_features(const std::vector<Frame>& fr, double leg_end, double cell,
                     const FeatureSettings& s, Features& F) {
  std::vector<double> xs, tops, bots;
  for (std::size_t i = s.impact_frames; i < fr.size(); ++i) {
    if (fr[i].eps < s.propagation_start * leg_end || fr[i].eps > leg_end) continue;
    xs.push_back(fr[i].eps);
    tops.push_back(fr[i].sigma_top);
    bots.push_back(std::abs(fr[i].sigma_bottom));
  }
  const double mt = median(tops), mb = median(bots);
  F.stress_ratio = std::isfinite(mt) ? mt / std::max(mb, s.bottom_floor * std::abs(mt)) : kNaN;

  if (!(std::isfinite(F.band_speed_ratio) && F.band_speed_ratio > 0 && mt > 0 &&
        xs.size() >= static_cast<std::size_t>(s.undulation_min_frames))) {
    return;
  }
  const double P = cell / F.band_speed_ratio;
  const double span = xs.back() - xs.front(), d = xs.size() > 1 ? span / (xs.size() - 1) : 0;
  if (!(span >= s.undulation_periods * P && P >= s.undulation_sampling * d)) return;
  // Half a step of slack: the sum of the steps may round above period_max.
  for (double q = s.period_min; q <= s.period_max + 0.5 * s.period_step; q += s.period_step) {
    const Harmonic h = harmonic(xs, tops, q * P);
    if (h.share > F.undulation_share) {
      F.undulation_share = h.share;
      F.top_stress_undulation = h.amplitude / mt;
    }
  }
}

}  // namespace

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

FrontTiming front_timing(const FrontTracks& tracks, const Front& front, const FeatureSettings& s) {
  return {at_onset(front, first_activity(tracks), s), first_leg_end(front), passes_middle(front)};
}

MapAxes map_axes(const SceneParams& p, const RunResult& r) {
  MapAxes a;
  a.h0 = p.h0;
  a.unit_cell = p.unit_cell();
  a.eps.reserve(r.frames.size());
  for (const auto& f : r.frames) a.eps.push_back(f.eps);
  return a;
}

Features compute_features(const SceneParams& p, const RunResult& r, const FrontTracks& t,
                          const BandPath& band, const FeatureSettings& s) {
  Features F;
  F.eps_reached = r.eps_reached;
  const double phi = r.phi_discrete > 0 ? r.phi_discrete : p.phi;
  F.nonreflecting_speed = nonreflecting_band_speed(phi);
  const double cell = p.unit_cell() / p.h0;
  const Front* prim = primary_front(t);

  front_counts(t, s, F);
  F.coherence = coherence(t);
  band_features(prim, band, s.tracker.plate_zone * cell, F);
  F.peak_jump = peak_jump(r.spacetime, p.unit_cell(), s.tracker.abs_threshold);
  const int fy = strut_features(r.frames, s, F);
  if (fy >= 0) F.stress_drop = stress_drop(r.frames, fy, s);
  stress_features(r.frames, prim ? first_leg_end(*prim) : r.eps_reached, cell, s, F);
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
      {"band_speed_error", num(f.band_speed_error)},
      {"band_speed_transit", num(f.band_speed_transit)},
      {"band_speed_transit_error", num(f.band_speed_transit_error)},
      {"band_speed_early", num(f.band_speed_early)},
      {"band_speed_early_error", num(f.band_speed_early_error)},
      {"band_speed_lead", num(f.band_speed_lead)},
      {"band_speed_lead_error", num(f.band_speed_lead_error)},
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

namespace {

// One key of a stored features object into `out`; an absent key leaves the default.
void read_number(const nlohmann::json& j, const char* key, double& out) {
  const auto it = j.find(key);
  if (it == j.end()) return;
  if (it->is_null()) {
    out = std::numeric_limits<double>::quiet_NaN();
  } else if (it->is_number()) {
    out = it->get<double>();
  } else {
    throw std::invalid_argument(std::string("features.") + key + ": must be a number or null");
  }
}

void read_int(const nlohmann::json& j, const char* key, int& out) {
  const auto it = j.find(key);
  if (it == j.end()) return;
  if (!it->is_number_integer()) throw std::invalid_argument(std::string("features.") + key + ": must be an integer");
  const auto v = it->get<long long>();
  if (v < 0 || v > std::numeric_limits<int>::max()) {
    throw std::invalid_argument(std::string("features.") + key + ": must be a count, got " + std::to_string(v));
  }
  out = static_cast<int>(v);
}

void read_bool(const nlohmann::json& j, const char* key, bool& out) {
  const auto it = j.find(key);
  if (it == j.end()) return;
  if (!it->is_boolean()) throw std::invalid_argument(std::string("features.") + key + ": must be true or false");
  out = it->get<bool>();
}

void read_text(const nlohmann::json& j, const char* key, std::string& out) {
  const auto it = j.find(key);
  if (it == j.end()) return;
  if (!it->is_string()) throw std::invalid_argument(std::string("features.") + key + ": must be a string");
  out = it->get<std::string>();
}

}  // namespace

Features features_from_json(const nlohmann::json& j) {
  if (!j.is_object()) throw std::invalid_argument("features: must be an object");
  Features f;
  read_int(j, "n_fronts", f.n_fronts);
  read_int(j, "n_fronts_onset", f.n_fronts_onset);
  if (const auto it = j.find("onset_origins"); it != j.end()) {
    if (!it->is_array()) throw std::invalid_argument("features.onset_origins: must be an array of strings");
    for (const auto& o : *it) {
      if (!o.is_string()) throw std::invalid_argument("features.onset_origins: must be an array of strings");
      f.onset_origins.push_back(o.get<std::string>());
    }
  }
  read_bool(j, "top_front", f.top_front);
  read_bool(j, "bottom_front", f.bottom_front);
  read_bool(j, "two_sided", f.two_sided);
  read_text(j, "primary_origin", f.primary_origin);
  read_int(j, "n_reflections", f.n_reflections);
  read_number(j, "first_reflection_eps", f.first_reflection_eps);
  read_int(j, "band_turns", f.band_turns);
  read_number(j, "band_speed_ratio", f.band_speed_ratio);
  read_number(j, "band_speed_error", f.band_speed_error);
  read_number(j, "band_speed_transit", f.band_speed_transit);
  read_number(j, "band_speed_transit_error", f.band_speed_transit_error);
  read_number(j, "band_speed_early", f.band_speed_early);
  read_number(j, "band_speed_early_error", f.band_speed_early_error);
  read_number(j, "band_speed_lead", f.band_speed_lead);
  read_number(j, "band_speed_lead_error", f.band_speed_lead_error);
  read_number(j, "bottom_speed_ratio", f.bottom_speed_ratio);
  read_number(j, "nonreflecting_speed", f.nonreflecting_speed);
  read_number(j, "speed_excess", f.speed_excess);
  read_number(j, "arrival_eps", f.arrival_eps);
  read_number(j, "coherence", f.coherence);
  read_number(j, "peak_jump", f.peak_jump);
  read_number(j, "stress_ratio", f.stress_ratio);
  read_number(j, "top_stress_undulation", f.top_stress_undulation);
  read_number(j, "undulation_share", f.undulation_share);
  read_number(j, "stress_drop", f.stress_drop);
  read_number(j, "eps_first_yield", f.eps_first_yield);
  read_number(j, "deflection_before_yield", f.deflection_before_yield);
  read_number(j, "deflection_growth", f.deflection_growth);
  read_number(j, "eps_reached", f.eps_reached);
  return f;
}

}  // namespace compaction::classify
