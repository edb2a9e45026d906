// The paper's non-reflecting band (class a: S = 4e-3, R = 1e-5, phi = 0.4, pseudo-1D), to
// eps = 0.15, at 16 cells per unit cell (what must hold at any resolution), at 40 (the
// paper's band speed, which needs the pores to close completely behind the front) and at 20
// with two velocity fields across closing pores (the default preset's contact).
//
// What must hold at any resolution, and is checked here:
// - one front leaves the top plate and moves down steadily;
// - mass conservation across the front: c_b / V = 1 / (1 - phi / phi_f), with phi_f the solid
//   fraction behind it, so c_b / V >= 1 / (1 - phi) (phi_f <= 1), and the measured speed agrees
//   with the one predicted from the measured phi_f;
// - kinematics of a band (velocity.npy): the compacted zone moves with the plate (row velocity
//   -V) and the material ahead of the front is at rest;
// - volume consistency of the compacted zone: the particles' area sum J V0 never exceeds the
//   zone's area (pores closed, not particles overlapping), and J stays ~1 (the solid is
//   elastically stiff, R = 1e-5, and plastically incompressible).
// The paper's c_b / V = 1 / (1 - phi) needs phi_f = 1 behind the front. Struts only a few cells
// thick leave the pores partly open (phi_f < 1), so c_b / V is larger, by an excess that falls
// with resolution (docs/engine.md, "Known limitation"): +23 % at 16 cells per unit cell (the
// first test records it and checks the invariants), +3.4 % at 40 (the second test checks that
// it stays within 5 %). Two velocity fields across closing pores bring it within 5 % at 20 (the
// third test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "compaction/simulation.hpp"

namespace compaction {
namespace {

struct Band {
  std::vector<double> eps, front;  // front height / h0 per frame
};

// The front in each frame: the lowest row whose plastic strain rate reaches 20 % of the frame's
// largest (rows above the plate hold 0).
Band track_front(const RunResult& r) {
  Band b;
  const SpaceTimeMap& m = r.spacetime;
  for (int f = 0; f < m.n_frames; ++f) {
    float peak = 0;
    for (int row = 0; row < m.n_rows; ++row) peak = std::max(peak, m.at(f, row));
    int lowest = m.n_rows - 1;
    for (int row = 0; row < m.n_rows; ++row) {
      if (m.at(f, row) >= 0.2f * peak) {
        lowest = row;
        break;
      }
    }
    b.eps.push_back(r.frames[f].eps);
    b.front.push_back((lowest + 0.5) / m.n_rows);
  }
  return b;
}

// Least-squares slope of y(x) over the points with x >= x0.
double slope(const std::vector<double>& x, const std::vector<double>& y, double x0) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] < x0) continue;
    n += 1, sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Frames in which the front jumps back up by more than 2 % of h0 (a reflection).
int rises(const Band& band) {
  int n = 0;
  for (std::size_t f = 1; f < band.front.size(); ++f) n += band.front[f] > band.front[f - 1] + 0.02;
  return n;
}

// c_b / V = -(1/h0) d y_front / d eps, fitted from eps = 0.03 on (past the front's start).
double band_speed(const Band& band) { return -slope(band.eps, band.front, 0.03); }

// The compacted zone at the run's snapshot: from one unit cell behind the front to one below the
// plate; its solid fraction phi_f (particle areas J V0 over the zone's area) and the range of J.
struct Zone {
  std::size_t frame = 0;  // the snapshot's frame
  double lo = 0, hi = 0;  // the zone's bounds [m]
  double phi_f = 0, j_min = 2, j_max = 0;
};

Zone compacted_zone(const SceneParams& p, const RunResult& r, const Band& band) {
  const Snapshot& s = r.snapshots.at(0);
  const double L = p.unit_cell(), v0 = std::pow(r.dx / p.particles_per_cell, 2);
  Zone z;
  z.frame = static_cast<std::size_t>(std::lround(s.eps / p.d_eps)) - 1;
  z.lo = band.front[z.frame] * p.h0 + L, z.hi = p.h0 * (1.0 - s.eps) - L;
  double area = 0;
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    if (s.y[k] < z.lo || s.y[k] >= z.hi) continue;
    area += s.jacobian[k] * v0;
    z.j_min = std::min<double>(z.j_min, s.jacobian[k]);
    z.j_max = std::max<double>(z.j_max, s.jacobian[k]);
  }
  z.phi_f = area / ((z.hi - z.lo) * p.width());
  return z;
}

SceneParams band_scene(int cells_per_unit) {
  SceneParams p;
  p.S = 4e-3, p.R = 1e-5, p.phi = 0.4;
  p.cells_per_unit = cells_per_unit;
  p.eps_end = 0.15;
  p.snapshot_eps = {0.12};
  p.pore_contact = PoreContact::single_field;  // one velocity field, unless a test says two
  return p;
}

TEST(CompactionBandGtest, NonReflectingBandConservesMassAndClosesPoresWithoutOverlap) {
  const SceneParams p = band_scene(16);
  const RunResult r = run_scene(p);
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;

  // One front from the top plate, moving down through the specimen.
  const Band band = track_front(r);
  EXPECT_GT(band.front[2], 0.9);  // starts at the top plate
  EXPECT_EQ(rises(band), 0) << "the front must not jump back up (no reflection before eps = 0.15)";
  const double cb = band_speed(band);
  const double bound = 1.0 / (1.0 - r.phi_discrete);
  RecordProperty("band_speed_ratio", std::to_string(cb));
  RecordProperty("band_speed_over_paper", std::to_string(cb / (1.0 / (1.0 - p.phi))));
  EXPECT_GE(cb, 0.97 * bound) << "slower than full densification allows";

  // The compacted zone at the snapshot: its solid fraction phi_f predicts the band speed by
  // mass conservation.
  const double L = p.unit_cell();
  const auto [frame, lo, hi, phi_f, j_min, j_max] = compacted_zone(p, r, band);
  ASSERT_GT(hi - lo, 2 * L);

  // Kinematics at the same frame: next to the plate the zone moves with it (-V); a unit cell
  // ahead of the front (two unit cells: the struts next to it already give way) the material is
  // at rest; in between, the velocity falls by less than the
  // zone's remaining porosity allows (its pores keep closing slowly while phi_f < 1: the mean
  // velocity of the zone is -V (1 - (1 - phi_f) * O(1))). Tolerances: 3 % of V next to the
  // plate; 5 % of V ahead, where the rows' mean velocity carries the ringing of the struts
  // (measured 2.4 % at 16 cells per unit cell; the elastic precursor alone moves them at ~0.2 %).
  const SpaceTimeMap& v = r.velocity;
  ASSERT_EQ(v.n_frames, r.spacetime.n_frames);
  const int fr = static_cast<int>(frame);
  double behind = 0, n_behind = 0, plate = 0, n_plate = 0, ahead = 0;
  for (int row = 0; row < v.n_rows; ++row) {
    const double y = (row + 0.5) * v.row_height;
    if (y >= lo && y < hi) behind += v.at(fr, row), n_behind += 1;
    if (y >= hi - L && y < hi) plate += v.at(fr, row), n_plate += 1;
    if (y < band.front[frame] * p.h0 - 2 * L) {
      ahead = std::max(ahead, std::abs(static_cast<double>(v.at(fr, row))));
    }
  }
  RecordProperty("velocity_behind_front", std::to_string(behind / n_behind));
  RecordProperty("velocity_next_to_plate", std::to_string(plate / n_plate));
  RecordProperty("largest_velocity_ahead_of_front", std::to_string(ahead));
  EXPECT_NEAR(plate / n_plate, -1.0, 0.03);
  EXPECT_LT(ahead, 0.05);
  EXPECT_LT(behind / n_behind, -1.0 + 2.0 * (1.0 - phi_f) + 0.03);
  EXPECT_GT(behind / n_behind, -1.03);
  RecordProperty("phi_behind_front", std::to_string(phi_f));
  // No overlap: tolerance 1 %, the zone's edges cut through particles of spacing dx/2.
  EXPECT_LE(phi_f, 1.01);
  EXPECT_GT(j_min, 0.99);
  EXPECT_LT(j_max, 1.01);
  // Mass conservation across the front, with phi_f varying behind it: within 15 %.
  const double predicted = 1.0 / (1.0 - r.phi_discrete / phi_f);
  RecordProperty("band_speed_from_mass_conservation", std::to_string(predicted));
  EXPECT_NEAR(cb / predicted, 1.0, 0.15);
}

// At 40 cells per unit cell (struts 9-18 cells thick) the band runs within 5 % of
// 1 / (1 - phi) = 1.667 (the excess falls roughly as dx^1.8, docs/engine.md, "Known
// limitation"). 87 000 particles, 119 000 steps: the slowest test of the engine.
TEST(CompactionBandGtest, NonReflectingBandRunsAtThePapersSpeedWhenStrutsAreResolved) {
  const SceneParams p = band_scene(40);
  const RunResult r = run_scene(p);
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;
  const Band band = track_front(r);
  EXPECT_EQ(rises(band), 0) << "the front must not jump back up (no reflection before eps = 0.15)";
  const double cb = band_speed(band);
  const double paper = 1.0 / (1.0 - p.phi);
  RecordProperty("band_speed_ratio", std::to_string(cb));
  EXPECT_NEAR(cb / paper, 1.0, 0.05);
}

// Two velocity fields across closing pores (pore_contact = split_fields, what the default preset
// runs) at the default preset's 20 cells per unit cell: the faces of a pore meet before they
// interact, so the pores close behind the front and the band runs at the paper's speed. The
// engine issue's target: within 5 % of 1 / (1 - phi) at the default preset (measured here
// 1.732, +3.9 %; +2.7 % by the fit to eps = 0.2 of studies/pore_contact/results/pore-contact.md), where one
// field gives +14 % at 20 cells (docs/engine.md). The pores close behind the front: phi_f above
// 0.9, where one field leaves 0.84 at 20 cells (docs/engine.md; measured here 0.909 at the
// snapshot, eps = 0.12: slits of a cell or less stay until the merge at an eighth of a cell),
// the band speed mass conservation predicts from it within 15 % as in the 16-cell test, and J
// within 1 % of 1: no overlap. About 0.3 of the 40-cell test's cost.
TEST(CompactionBandGtest, TwoFieldsRunTheBandAtThePapersSpeedAtTheDefaultResolution) {
  SceneParams p = band_scene(20);
  p.pore_contact = PoreContact::split_fields;
  const RunResult r = run_scene(p);
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;
  const Band band = track_front(r);
  EXPECT_EQ(rises(band), 0) << "the front must not jump back up (no reflection before eps = 0.15)";
  const double cb = band_speed(band);
  const double paper = 1.0 / (1.0 - p.phi);
  RecordProperty("band_speed_ratio", std::to_string(cb));
  EXPECT_NEAR(cb / paper, 1.0, 0.05);
  const Zone z = compacted_zone(p, r, band);
  RecordProperty("phi_behind_front", std::to_string(z.phi_f));
  EXPECT_GT(z.phi_f, 0.9);
  EXPECT_LE(z.phi_f, 1.01);
  EXPECT_GT(z.j_min, 0.99);
  EXPECT_LT(z.j_max, 1.01);
  EXPECT_NEAR(cb * (1.0 - r.phi_discrete / z.phi_f), 1.0, 0.15);
}

}  // namespace
}  // namespace compaction
