// What the tests of threaded stages share (transfer_gtest, pore_contact_gtest,
// grid_update_gtest): a scene sized for another pool than its own, and the check that two grids
// hold the same nodes.
#pragma once

#include <gtest/gtest.h>

#include <cstring>

#include "state.hpp"

namespace compaction {

// Gives the scene's grid and per-thread sums what a pool of `threads` needs (build_scene sizes
// them for p.threads).
inline void size_for_threads(State& s, int threads) {
  s.partial_measures.resize(static_cast<std::size_t>(threads));
  s.partial_impulses.resize(static_cast<std::size_t>(threads));
}

// Every node of b (both fields, PIC/FLIP's momenta, the normals) holds what a's holds, bit for
// bit: the threaded stages add in one order whatever the number of threads.
inline void expect_same_nodes(const State& a, const State& b) {
  const NodeArrays& x = a.grid.arrays;
  const NodeArrays& y = b.grid.arrays;
  ASSERT_EQ(x.nodes.size(), y.nodes.size());
  for (std::size_t i = 0; i < x.nodes.size(); ++i) {
    ASSERT_EQ(std::memcmp(&x.nodes[i], &y.nodes[i], sizeof(Node)), 0)
        << "node " << i << ": m " << x.nodes[i].m << " " << y.nodes[i].m;
  }
  EXPECT_EQ(x.mx, y.mx);
  EXPECT_EQ(x.my, y.my);
  ASSERT_EQ(x.normal.size(), y.normal.size());
  for (std::size_t i = 0; i < x.normal.size(); ++i) {
    ASSERT_EQ(x.normal[i].x, y.normal[i].x) << i;
    ASSERT_EQ(x.normal[i].y, y.normal[i].y) << i;
  }
}

}  // namespace compaction
