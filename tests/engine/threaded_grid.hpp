// What the tests of threaded stages share (transfer_gtest, pore_contact_gtest,
// grid_update_gtest): a scene sized for another pool than its own, and the check that two grids
// hold the same nodes.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "state.hpp"

namespace compaction {

// Gives the scene's grid and per-thread sums what a pool of `threads` needs (build_scene sizes
// them for p.threads).
inline void size_for_threads(State& s, int threads) {
  s.grid.scratch.assign(static_cast<std::size_t>(threads - 1), s.grid.arrays);
  s.grid.scatter_rows.resize(threads, s.grid.ny);
  s.partial_measures.resize(static_cast<std::size_t>(threads));
  s.partial_impulses.resize(static_cast<std::size_t>(threads));
}

// Every node of b (both fields, PIC/FLIP's momenta) holds what a's holds, to 1e-15 of the
// grid's largest mass or momentum: the threads' sums differ from the serial ones by the order
// of a few additions (4e-16 measured). split_fields lists the same nodes in both, with the same
// normals.
inline void expect_same_nodes(const State& a, const State& b) {
  const NodeArrays& x = a.grid.arrays;
  const NodeArrays& y = b.grid.arrays;
  ASSERT_EQ(x.nodes.size(), y.nodes.size());
  double m_scale = 0, p_scale = 0;
  for (const Node& n : x.nodes) {
    m_scale = std::max(m_scale, n.m), p_scale = std::max(p_scale, std::hypot(n.vx, n.vy));
  }
  for (std::size_t i = 0; i < x.nodes.size(); ++i) {
    ASSERT_NEAR(x.nodes[i].m, y.nodes[i].m, 1e-15 * m_scale) << i;
    ASSERT_NEAR(x.nodes[i].vx, y.nodes[i].vx, 1e-15 * p_scale) << i;
    ASSERT_NEAR(x.nodes[i].vy, y.nodes[i].vy, 1e-15 * p_scale) << i;
  }
  for (std::size_t i = 0; i < x.mx.size(); ++i) {
    ASSERT_NEAR(x.mx[i], y.mx[i], 1e-15 * p_scale) << i;
    ASSERT_NEAR(x.my[i], y.my[i], 1e-15 * p_scale) << i;
  }
  ASSERT_EQ(a.grid.split.nodes, b.grid.split.nodes);
  for (const std::uint32_t k : a.grid.split.nodes) {
    ASSERT_EQ(a.grid.split.normal[k].x, b.grid.split.normal[k].x) << k;
    ASSERT_EQ(a.grid.split.normal[k].y, b.grid.split.normal[k].y) << k;
  }
}

}  // namespace compaction
