// Front detection (active segments per frame) and tracking (segments linked over frames).
#include "compaction/classify/fronts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "line_fit.hpp"
#include "turns.hpp"

namespace compaction::classify {

const char* to_string(Origin o) {
  switch (o) {
    case Origin::top: return "top";
    case Origin::bottom: return "bottom";
    case Origin::interior: return "interior";
  }
  return "?";
}

double Front::mass() const {
  double m = 0.0;
  for (const auto& s : path) m += s.shared ? 0.5 * s.mass : s.mass;  // a crossing shares it
  return m;
}

namespace {

// Lengths of the tracker in units of h0, from the settings in unit cells.
struct Scales {
  double row = 0.0;        // row height / h0
  double cell = 0.0;       // unit cell / h0
  int smooth_rows = 0;     // half-width of the box filter
  int merge_rows = 0;      // largest gap inside one segment
  double link = 0.0, zone = 0.0, travel = 0.0, turn = 0.0, margin = 0.0, extent = 0.0;
};

Scales make_scales(const SpaceTimeMap& map, const MapAxes& axes, const TrackerSettings& s) {
  Scales k;
  k.row = map.row_height / axes.h0;
  k.cell = axes.unit_cell / axes.h0;
  const double rows_per_cell = axes.unit_cell / map.row_height;
  k.smooth_rows = static_cast<int>(std::lround(s.smooth * rows_per_cell));
  k.merge_rows = static_cast<int>(std::lround(s.merge_gap * rows_per_cell));
  k.link = s.link_tol * k.cell;
  k.zone = s.plate_zone * k.cell;
  k.travel = s.min_travel * k.cell;
  k.margin = s.fit_margin * k.cell;
  k.turn = s.turn_travel * k.cell;
  k.extent = s.max_extent;
  return k;
}

// One frame's profile, box-filtered over +-w rows (plastic activity of one strut is spread over
// the rows it spans; the filter keeps a strut's activity in one segment).
std::vector<double> smoothed_profile(const SpaceTimeMap& map, int f, int w) {
  std::vector<double> p(map.n_rows, 0.0);
  for (int r = 0; r < map.n_rows; ++r) {
    double sum = 0.0;
    int n = 0;
    for (int q = std::max(0, r - w); q <= std::min(map.n_rows - 1, r + w); ++q, ++n) {
      sum += map.at(f, q);
    }
    p[r] = sum / n;
  }
  return p;
}

std::vector<Segment> detect_segments(const SpaceTimeMap& map, int f, double eps,
                                     const Scales& k, const TrackerSettings& s) {
  const std::vector<double> p = smoothed_profile(map, f, k.smooth_rows);
  const double peak = *std::max_element(p.begin(), p.end());
  std::vector<Segment> out;
  if (!(peak > s.abs_threshold)) return out;
  const double thr = std::max(s.rel_threshold * peak, s.abs_threshold);
  int r = 0;
  while (r < map.n_rows) {
    if (p[r] <= thr) { ++r; continue; }
    int end = r;  // last active row of this segment
    int q = r + 1;
    while (q < map.n_rows) {
      if (p[q] > thr) { end = q; ++q; continue; }
      if (q - end > k.merge_rows) break;
      ++q;
    }
    Segment seg;
    seg.frame = f;
    seg.eps = eps;
    seg.lo = r * k.row;
    seg.hi = (end + 1) * k.row;
    double wsum = 0.0, ysum = 0.0;
    for (int i = r; i <= end; ++i) {
      if (p[i] <= thr) continue;
      wsum += p[i];
      ysum += p[i] * (i + 0.5) * k.row;
      seg.peak = std::max(seg.peak, p[i]);
    }
    seg.centroid = ysum / wsum;
    seg.mass = wsum * k.row;
    out.push_back(seg);
    r = end + 1;
  }
  return out;
}

double top_of(double eps) { return 1.0 - eps; }  // the top plate's height / h0

// A segment spanning much of the specimen is diffuse activity, not a front's position.
bool diffuse(const Segment& g, const Scales& k) { return g.hi - g.lo > k.extent * top_of(g.eps); }

// Where a segment touches: the top plate, the bottom plate or neither.
Origin where(const Segment& g, const Scales& k) {
  if (g.hi >= top_of(g.eps) - k.zone) return Origin::top;
  if (g.lo <= k.zone) return Origin::bottom;
  return Origin::interior;
}

// The last segment that is the front's own (not shared with a crossing front).
const Segment& last_own(const Front& fr) {
  for (auto it = fr.path.rbegin(); it != fr.path.rend(); ++it) {
    if (!it->shared) return *it;
  }
  return fr.path.front();
}

// Velocity of a front's centroid in h0 per frame from its last few own segments; zero while it
// sits at a plate, where it may turn.
double velocity(const Front& fr, const Scales& k, const TrackerSettings& s) {
  std::vector<const Segment*> own;
  const std::size_t count = static_cast<std::size_t>(s.velocity_segments);
  for (auto it = fr.path.rbegin(); it != fr.path.rend() && own.size() < count; ++it) {
    if (!it->shared) own.push_back(&*it);
  }
  if (own.size() < 2 || where(*own.front(), k) != Origin::interior) return 0.0;
  const Segment& a = *own.back();
  const Segment& b = *own.front();
  return (b.centroid - a.centroid) / std::max(1, b.frame - a.frame);
}

double gap(double lo1, double hi1, double lo2, double hi2) {
  return std::max(0.0, std::max(lo1, lo2) - std::min(hi1, hi2));
}

// Turns of the centroid (turns.hpp). The front sets off once it is min_travel from where it
// started; a turn at its extreme is a reflection when the front's leading edge is in the zone of
// the plate it came to. Diffuse and shared segments give no position.
void find_turns(Front& fr, const Scales& k) {
  const auto& p = fr.path;
  TurnFollower follower(k.turn);
  const double c0 = p.front().centroid;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (diffuse(p[i], k) || p[i].shared) continue;
    const double c = p[i].centroid;
    fr.travel = std::max(fr.travel, std::abs(c - c0));
    if (!follower.moving()) {
      if (std::abs(c - c0) >= k.travel) follower.set_off(c > c0 ? 1 : -1, i, c);
      continue;
    }
    const std::optional<Turn> turn = follower.next(i, c);
    if (!turn) continue;
    const Segment& g = p[turn->index];
    TurningPoint t;
    t.index = static_cast<int>(turn->index);
    t.eps = g.eps;
    if (turn->came < 0 && g.lo <= k.zone) t.where = Origin::bottom;
    else if (turn->came > 0 && g.hi >= top_of(g.eps) - k.zone) t.where = Origin::top;
    fr.turns.push_back(t);
    if (t.where != Origin::interior) ++fr.n_reflections;
  }
}

// The speed of the leading edge over the part before the first turn, away from both plates, read
// two ways: the least-squares slope through every point (with its standard error), and the mean
// speed between the first and the last point (travel / strain), which a band that slows down
// or whose tracked branch changes on the way cannot pull towards a later slope. The leading edge
// is the lower edge of a front moving down, the upper edge of one moving up.
void fit_speed(Front& fr, const Scales& k, double frame_eps, const TrackerSettings& s) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  fr.speed = fr.speed_error = fr.transit_speed = fr.transit_error = nan;
  fr.leg_edge.clear();
  const auto& p = fr.path;
  const std::size_t last = fr.turns.empty() ? p.size() - 1 : fr.turns.front().index;
  const bool down = p[last].centroid < p.front().centroid;
  LineFit fit;
  for (std::size_t i = 0; i <= last; ++i) {
    if (diffuse(p[i], k) || p[i].shared) continue;
    const double y = down ? p[i].lo : p[i].hi;
    if (y < k.margin || y > top_of(p[i].eps) - k.margin) continue;
    fit.add(p[i].eps, y);
    fr.leg_edge.push_back({p[i].eps, y});
  }
  if (fit.n < s.min_fit_points || !fit.has_slope()) return;
  const double slope = fit.slope();  // h0 per unit imposed strain = speed / V
  fr.speed = down ? -slope : slope;
  fr.speed_error = fit.slope_standard_error();
  const auto [eps_first, y_first] = fr.leg_edge.front();
  const auto [eps_last, y_last] = fr.leg_edge.back();
  const double travel = down ? y_first - y_last : y_last - y_first, strain = eps_last - eps_first;
  fr.transit_speed = travel / strain;
  // Each end is known to one row in height and half a frame in strain, and in a structured
  // column it lies anywhere on a step of the edge: the edge stands while a row of pores closes
  // and then moves on by a unit cell, so an end sits up to a cell off the leg's mean line
  // (standard deviation cell / sqrt(12)).
  const double dy_end = std::hypot(k.row, k.cell / std::sqrt(12.0));
  const double dy = std::sqrt(2.0) * dy_end, de = std::sqrt(2.0) * 0.5 * frame_eps;
  fr.transit_error = std::abs(fr.transit_speed) * std::hypot(dy / travel, de / strain);
}

// Where a front is expected in frame f: its last own segment moved on with its velocity.
struct Prediction { double lo, hi, centroid; };
Prediction predict(const Front& fr, int f, const Scales& k, const TrackerSettings& s) {
  const Segment& b = last_own(fr);
  const double shift = velocity(fr, k, s) * (f - b.frame);
  return {b.lo + shift, b.hi + shift, b.centroid + shift};
}

// A possible continuation of front `front` by segment `seg` of the frame; closest first.
struct Link { double distance; int seg, front; };

// The fronts being followed and the frame each was last seen in.
struct Linking {
  std::vector<Front>& fronts;
  std::vector<int> last_seen;
};

// Live fronts whose predicted interval is within link_tol of a segment, closest centroid first.
std::vector<Link> candidate_links(const Linking& L, const std::vector<Segment>& segs, int f,
                                  const Scales& k, const TrackerSettings& s) {
  std::vector<Link> links;
  for (int j = 0; j < static_cast<int>(L.fronts.size()); ++j) {
    if (f - L.last_seen[j] > s.max_missing + 1) continue;
    const Prediction at = predict(L.fronts[j], f, k, s);
    for (int i = 0; i < static_cast<int>(segs.size()); ++i) {
      if (gap(at.lo, at.hi, segs[i].lo, segs[i].hi) > k.link) continue;
      links.push_back({std::abs(segs[i].centroid - at.centroid), i, j});
    }
  }
  std::sort(links.begin(), links.end(), [](const Link& a, const Link& b) {
    if (a.distance != b.distance) return a.distance < b.distance;
    return a.front != b.front ? a.front < b.front : a.seg < b.seg;
  });
  return links;
}

// Where a new front in frame f with segment g starts: the plate it touches, or, when it is
// within link_tol of a front seen in this frame, that front's origin (it splits off it; the
// nearest such front).
Origin origin_of_new(const Linking& L, const Segment& g, int f, const Scales& k) {
  Origin origin = where(g, k);
  double nearest = k.link;
  for (std::size_t j = 0; j < L.last_seen.size(); ++j) {
    if (L.last_seen[j] != f) continue;
    const Segment& b = L.fronts[j].path.back();
    const double d = gap(b.lo, b.hi, g.lo, g.hi);
    if (d <= nearest) { nearest = d; origin = L.fronts[j].origin; }
  }
  return origin;
}

// Links one frame's segments to the fronts (greedy, closest first, one segment per front); a
// front left over that crosses a taken segment shares it; every segment left over starts a
// front.
void link_frame(Linking& L, const std::vector<Segment>& segs, int f, const Scales& k,
                const TrackerSettings& s) {
  const std::vector<Link> links = candidate_links(L, segs, f, k, s);
  std::vector<bool> seg_used(segs.size(), false), front_used(L.fronts.size(), false);
  for (const auto& ln : links) {
    if (seg_used[ln.seg] || front_used[ln.front]) continue;
    seg_used[ln.seg] = front_used[ln.front] = true;
    L.fronts[ln.front].path.push_back(segs[ln.seg]);
    L.last_seen[ln.front] = f;
  }
  // A live front left without a segment whose predicted interval overlaps a taken segment
  // has merged with another front (they cross): it shares that segment.
  for (const auto& ln : links) {
    if (front_used[ln.front] || !seg_used[ln.seg]) continue;
    const Prediction at = predict(L.fronts[ln.front], f, k, s);
    if (gap(at.lo, at.hi, segs[ln.seg].lo, segs[ln.seg].hi) > 0.0) continue;
    Segment g = segs[ln.seg];
    g.shared = true;
    for (auto& other : L.fronts) {
      if (!other.path.empty() && other.path.back().frame == f && other.path.back().lo == g.lo) {
        other.path.back().shared = true;
      }
    }
    L.fronts[ln.front].path.push_back(g);
    front_used[ln.front] = true;
    L.last_seen[ln.front] = f;
  }
  for (std::size_t i = 0; i < segs.size(); ++i) {
    if (seg_used[i]) continue;
    Front fr;
    fr.origin = origin_of_new(L, segs[i], f, k);
    fr.path.push_back(segs[i]);
    L.fronts.push_back(fr);
    L.last_seen.push_back(f);
  }
}

}  // namespace

FrontTracks track_fronts(const SpaceTimeMap& map, const MapAxes& axes, const TrackerSettings& s) {
  if (static_cast<int>(axes.eps.size()) != map.n_frames) {
    throw std::invalid_argument("track_fronts: " + std::to_string(axes.eps.size()) +
                                " strains for " + std::to_string(map.n_frames) + " frames");
  }
  if (map.n_rows <= 0 || !(map.row_height > 0) || !(axes.unit_cell > 0) || !(axes.h0 > 0)) {
    throw std::invalid_argument("track_fronts: empty map or non-positive lengths");
  }
  const Scales k = make_scales(map, axes, s);
  FrontTracks out;
  out.segments.resize(map.n_frames);
  Linking linking{out.fronts, {}};
  for (int f = 0; f < map.n_frames; ++f) {
    out.segments[f] = detect_segments(map, f, axes.eps[f], k, s);
    for (const auto& g : out.segments[f]) out.total_mass += g.mass;
    link_frame(linking, out.segments[f], f, k, s);
  }
  // The strain between frames (the maps' frames are evenly spaced in strain).
  const double frame_eps =
      map.n_frames > 1 ? (axes.eps.back() - axes.eps.front()) / (map.n_frames - 1) : 0.0;
  for (auto& fr : out.fronts) {
    find_turns(fr, k);
    fr.propagating = fr.travel >= k.travel;
    fit_speed(fr, k, frame_eps, s);
  }
  return out;
}

}  // namespace compaction::classify
