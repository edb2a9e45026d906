// Contact across closing pores with two velocity fields (pore_contact = split_fields,
// engine/src/pore_contact.hpp): the face normals the scene builder gives the particles, the
// two fields holding exactly what one field holds, the faces of an open gap moving apart
// from each other's velocity, and the fields merged once the gap is closed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "kernel.hpp"
#include "pore_contact.hpp"
#include "scene_builder.hpp"
#include "stages.hpp"
#include "threaded_grid.hpp"

namespace compaction {
namespace {

SceneParams porous(PoreContact contact) {
  SceneParams p;
  p.n_rows = 4, p.cells_per_unit = 16, p.phi = 0.4, p.eps_end = 0.05;
  p.pore_contact = contact;
  return p;
}

// Every particle gets a velocity, an affine field and a stress (deterministic, irregular), so
// that P2G moves momentum and stress impulses into both fields.
void stir(State& s) {
  Particles& P = s.particles;
  for (std::size_t k = 0; k < P.n; ++k) {
    const double a = std::sin(1.3 * k), b = std::cos(0.7 * k);
    P.vx[k] = 0.3 * a, P.vy[k] = -0.2 * b;
    P.C.set(k, {0.5 * b, -0.1 * a, 0.2 * a, -0.4 * b});
    P.tau.set(k, {40.0 * a, 15.0 * b, -25.0 * a * b});
  }
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
}

TEST(PoreContactGtest, NormalsPointFromTheNearestPoreFaceIntoTheSolid) {
  const SceneParams p = porous(PoreContact::split_fields);
  const State s = build_scene(p);
  const Particles& P = s.particles;
  ASSERT_EQ(P.nx.size(), P.n);
  const double L = p.unit_cell(), half_hole = 0.5 * p.hole_side();
  int bar_below = 0, bar_above = 0, strut_left = 0, strut_right = 0;
  for (std::size_t k = 0; k < P.n; ++k) {
    EXPECT_NEAR(std::hypot(P.nx[k], P.ny[k]), 1.0, 1e-12);
    // Position within the unit cell, the pore centred at (L/2, L/2).
    const double u = P.x[k] - L * std::floor(P.x[k] / L) - 0.5 * L;
    const double v = P.y[k] - L * std::floor(P.y[k] / L) - 0.5 * L;
    // Away from the bar's and the strut's middles, where the nearest face changes.
    const double dx = s.grid.dx;
    if (std::abs(u) < 0.25 * half_hole && v > half_hole && v < 0.5 * L - dx) {
      EXPECT_NEAR(P.ny[k], 1.0, 1e-12) << k;  // the bar above the pore: n = +y
      ++bar_above;
    }
    if (std::abs(u) < 0.25 * half_hole && v < -half_hole && v > -0.5 * L + dx) {
      EXPECT_NEAR(P.ny[k], -1.0, 1e-12) << k;  // the bar below: n = -y
      ++bar_below;
    }
    if (std::abs(v) < 0.25 * half_hole && u > half_hole && u < 0.5 * L - dx) {
      EXPECT_NEAR(P.nx[k], 1.0, 1e-12) << k;  // the strut right of the pore: n = +x
      ++strut_right;
    }
    if (std::abs(v) < 0.25 * half_hole && u < -half_hole && u > -0.5 * L + dx) {
      EXPECT_NEAR(P.nx[k], -1.0, 1e-12) << k;  // the strut left of it: n = -x
      ++strut_left;
    }
  }
  EXPECT_GT(bar_above, 0);
  EXPECT_GT(bar_below, 0);
  EXPECT_GT(strut_left, 0);
  EXPECT_GT(strut_right, 0);
  // The default keeps no normals.
  EXPECT_TRUE(build_scene(porous(PoreContact::single_field)).particles.nx.empty());
}

TEST(PoreContactGtest, TheTwoFieldsOfANodeHoldWhatOneFieldHolds) {
  State one = build_scene(porous(PoreContact::single_field));
  State two = build_scene(porous(PoreContact::split_fields));
  stir(one), stir(two);
  ThreadPool pool(1);
  const double dt = 1e-6;
  p2g(one, dt, pool);
  p2g(two, dt, pool);
  const auto& a = one.grid.arrays.nodes;
  ASSERT_EQ(two.grid.field2, a.size());
  const Node* f1 = two.grid.arrays.nodes.data();
  const Node* f2 = f1 + two.grid.field2;
  double m_scale = 0, p_scale = 0;
  for (const Node& n : a) {
    m_scale = std::max(m_scale, n.m);
    p_scale = std::max(p_scale, std::hypot(n.vx, n.vy));
  }
  int both = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(f1[k].m + f2[k].m, a[k].m, 1e-13 * m_scale) << k;
    EXPECT_NEAR(f1[k].vx + f2[k].vx, a[k].vx, 1e-12 * p_scale) << k;
    EXPECT_NEAR(f1[k].vy + f2[k].vy, a[k].vy, 1e-12 * p_scale) << k;
    both += f1[k].m > 0 && f2[k].m > 0;
  }
  // The strut's and the bars' halves meet inside the solid: their nodes carry both fields.
  EXPECT_GT(both, 0);
}

// With threads, each thread scatters its share of the one field into its own rows or its
// scratch (engine/src/scatter_rows.hpp), then the listed nodes are split on one thread: both
// fields are the serial ones to round-off, the listed nodes and their normals the same, and
// every particle's field bits name the field that the pair's test picks on a listed node (the
// first on any other), which g2p then reads without testing again.
TEST(PoreContactGtest, ThreadsFillTheTwoFieldsAsOneThreadDoes) {
  State a = build_scene(porous(PoreContact::split_fields));
  State b = build_scene(porous(PoreContact::split_fields));
  stir(a), stir(b);
  size_for_threads(b, 2);
  ThreadPool one(1), two(2);
  p2g(a, 1e-6, one);
  p2g(b, 1e-6, two);
  expect_same_nodes(a, b);  // both fields and the normals
  const Grid& g = b.grid;
  const Particles& P = b.particles;
  int second = 0;
  for (std::size_t p = 0; p < P.n; ++p) {
    const auto kx = kernel::quadratic(P.x[p] * g.inv_dx + g.gx);
    const auto ky = kernel::quadratic(P.y[p] * g.inv_dx + g.gy);
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        const std::size_t node =
            static_cast<std::size_t>(ky.base + j) * g.nx + g.col[kx.base + 1 + i];
        const NodeNormal m = g.split.normal[node];
        const bool test = g.split.node[node] != 0 &&  // a node not listed has one field
                          pore_contact::second_field(P.nx[p], P.ny[p], m.x, m.y);
        ASSERT_EQ(test, ((P.field_bits[p] >> (3 * j + i)) & 1u) != 0) << p;
        second += test;
      }
    }
    ASSERT_EQ(P.field_bits[p], a.particles.field_bits[p]) << p;
  }
  EXPECT_GT(second, 0);  // the strut's halves: some pairs go into the second field
}

// A solid column cut by a horizontal gap: the block below moves up, the one above down, as two
// faces of a closing pore do. Particles within gap_cells / 2 of the cut are removed; normals
// point from the gap into each block. The cut lies off the grid's nodes (0.3 dx above one), so
// that no node sits where the two faces' normals cancel exactly.
State closing_gap(double gap_cells, PoreContact contact, double u) {
  SceneParams p;
  p.n_rows = 4, p.cells_per_unit = 8, p.phi = 1.0, p.eps_end = 0.01;
  p.pore_contact = contact;
  State s = build_scene(p);
  Particles& P = s.particles;
  const double yc = 0.5 * p.h0 + 0.3 * s.grid.dx, half = 0.5 * gap_cells * s.grid.dx;
  const bool split = contact == PoreContact::split_fields;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < P.n; ++k) {
    if (std::abs(P.y[k] - yc) < half) continue;
    const bool above = P.y[k] > yc;
    P.x[kept] = P.x[k], P.y[kept] = P.y[k];
    P.vx[kept] = 0.0, P.vy[kept] = above ? -u : u;
    P.C.set(kept, {0, 0, 0, 0}), P.tau.set(kept, {0, 0, 0});
    if (split) P.nx[kept] = 0.0, P.ny[kept] = above ? 1.0 : -1.0;
    ++kept;
  }
  P.n = kept;
  s.grid.row_lo = 0, s.grid.row_hi = s.grid.ny;
  ThreadPool pool(1);
  p2g(s, 0.0, pool);
  grid_update(s, pool);
  return s;
}

TEST(PoreContactGtest, TheFacesOfAnOpenGapKeepTheirOwnVelocities) {
  const double u = 0.1;
  // Particles 1.5 cells apart across the cut (faces about a cell apart): one field averages
  // the faces' velocities on the nodes they share (the early contact); two fields leave each
  // face its own.
  const State one = closing_gap(1.0, PoreContact::single_field, u);
  const State two = closing_gap(1.0, PoreContact::split_fields, u);
  const Grid& g = two.grid;
  int shared = 0;
  for (int j = g.gy + 8; j < g.ny - g.gy - 8; ++j) {  // away from the plates
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * g.nx + i;
      const Node &a = g.arrays.nodes[k], &b = g.arrays.nodes[g.field2 + k];
      if (!(a.m > 0 && b.m > 0)) continue;
      ++shared;
      // Which field is which face depends on the node's normal; each holds one face's velocity.
      EXPECT_NEAR(std::abs(a.vy), u, 1e-12 * u) << "node " << k;
      EXPECT_NEAR(a.vy, -b.vy, 1e-12 * u) << "node " << k;
      EXPECT_LT(std::abs(one.grid.arrays.nodes[k].vy), u * (1 - 1e-3)) << "one field: averaged";
    }
  }
  EXPECT_GT(shared, 0) << "the faces share nodes across a cell";
}

// Once the gap is closed the nodes on the cut are full: they are not split (two fields would
// merge there), so the faces move as one field moves them, though their normals oppose.
TEST(PoreContactGtest, AClosedGapIsOneField) {
  const double u = 0.1;
  const State one = closing_gap(0.0, PoreContact::single_field, u);
  const State two = closing_gap(0.0, PoreContact::split_fields, u);
  const Grid& g = two.grid;
  int on_cut = 0;
  for (int j = g.gy + 8; j < g.ny - g.gy - 8; ++j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * g.nx + i;
      const Node &a = g.arrays.nodes[k], &b = g.arrays.nodes[g.field2 + k], &o = one.grid.arrays.nodes[k];
      EXPECT_EQ(b.m, 0.0) << "node " << k << ": no second field";
      EXPECT_NEAR(a.vy, o.vy, 1e-12 * u) << "node " << k << ": as one field";
      // The nodes within a cell of the cut (closing_gap's), which both faces reach: full.
      const double y = (j - g.gy) * g.dx, cut = 0.5 * two.setup.h0 + 0.3 * g.dx;
      if (std::abs(y - cut) > g.dx) continue;
      ++on_cut;
      EXPECT_GE(a.m, two.setup.merge_mass) << "node " << k;
    }
  }
  EXPECT_GT(on_cut, 0);
}

// The windows of normals (pore_contact::outside_windows): normals that may_oppose passes over
// lie within 90 degrees of each other (and so never put a particle in a node's second field);
// normals within 45 degrees of each other, and a pore corner's faces, are always passed over.
// Pairs of directions every 2.5 degrees, on the windows' ends and off them.
TEST(PoreContactGtest, WindowsPassOverNormalsWithin90Degrees) {
  using pore_contact::may_oppose, pore_contact::outside_windows;
  auto out = [](double degrees) {
    const double r = degrees * std::acos(-1.0) / 180.0;
    return static_cast<unsigned>(outside_windows(std::cos(r), std::sin(r)));
  };
  EXPECT_EQ(outside_windows(0.0, 0.0), 0);  // no pores: inside every window
  for (double d = 0.0; d < 360.0; d += 2.5) {
    for (double e = 0.0; e <= 180.0; e += 2.5) {
      const bool may = may_oppose(out(d) | out(d + e));
      if (e <= 45.0) {
        EXPECT_FALSE(may) << d << " and " << d + e;
      }
      if (e > 90.0) {
        EXPECT_TRUE(may) << d << " and " << d + e;
      }
    }
  }
  // The faces of a pore's corners, exactly perpendicular, and opposite faces.
  for (const auto& [ax, ay, bx, by] : {std::array{1, 0, 0, 1}, {0, 1, -1, 0}, {-1, 0, 0, -1},
                                       {0, -1, 1, 0}}) {
    EXPECT_FALSE(may_oppose(outside_windows(ax, ay) | outside_windows(bx, by)));
    EXPECT_TRUE(may_oppose(outside_windows(ax, ay) | outside_windows(-ax, -ay)));
  }
  const double h = std::sqrt(0.5);
  EXPECT_FALSE(may_oppose(outside_windows(h, h) | outside_windows(-h, h)));
}

}  // namespace
}  // namespace compaction
