// Which grid rows each P2G thread writes alone (p2g.cpp; p2g_3d.cpp, a row being a y-layer).
//
// A thread scatters a contiguous share of the particles, and the scene's lattice order keeps a
// share in a band of rows (particles move less than a cell per step and never far from their
// lattice neighbours). A particle whose three stencil rows no other thread reaches is added to
// the grid directly; any other goes into the thread's own scratch arrays (thread 0's into the
// grid as well), which are then summed into the grid, in thread order, over the rows within two
// of a row that several threads reach. So the threads clear and sum a few rows each instead of
// the whole grid, and the result does not depend on timing. Any order of the particles is still
// correct: a share spread over the column only makes more rows shared.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernel.hpp"

namespace compaction {

// The rows [lo, hi) that particles at heights y[begin, end) reach with their stencils, on a grid
// of spacing 1 / inv_dx whose row gy is at y = 0. A stencil's first row rises with y, so the
// lowest and the highest particle set them: a minimum and a maximum in eight lanes, a loop that
// vectorises (a NaN position, which the stability checks stop the run for, is passed over).
inline void stencil_rows(const double* __restrict y, std::size_t begin, std::size_t end,
                         double inv_dx, int gy, int& lo, int& hi) {
  constexpr std::size_t kLanes = 8;
  constexpr double inf = std::numeric_limits<double>::infinity();
  double y_min[kLanes], y_max[kLanes];
  std::fill(y_min, y_min + kLanes, inf);
  std::fill(y_max, y_max + kLanes, -inf);
  std::size_t p = begin;
  for (; p + kLanes <= end; p += kLanes) {
    for (std::size_t j = 0; j < kLanes; ++j) {
      y_min[j] = std::min(y_min[j], y[p + j]), y_max[j] = std::max(y_max[j], y[p + j]);
    }
  }
  for (std::size_t j = 0; p < end; ++p, ++j) {
    y_min[j] = std::min(y_min[j], y[p]), y_max[j] = std::max(y_max[j], y[p]);
  }
  const double lowest = *std::min_element(y_min, y_min + kLanes);
  const double highest = *std::max_element(y_max, y_max + kLanes);
  if (!(lowest <= highest)) {  // no particles (or none with a position)
    lo = hi = 0;
    return;
  }
  lo = kernel::quadratic(lowest * inv_dx + gy).base;
  hi = kernel::quadratic(highest * inv_dx + gy).base + 3;
}

struct ScatterRows {
  std::vector<int> lo, hi;          // thread t's particles reach rows [lo[t], hi[t])
  std::vector<std::uint8_t> alone;  // alone[b]: one thread at most reaches rows b, b + 1, b + 2
  std::vector<std::uint8_t> near;   // near[r]: within two rows of a row that several reach
  std::vector<int> count;           // threads that reach each row (plan's work array)

  // Sizes everything once, for a pool of `threads` and a grid of `rows` rows.
  void resize(int threads, int rows) {
    lo.assign(threads, 0), hi.assign(threads, 0);
    alone.assign(rows, 1), near.assign(rows, 0), count.assign(rows, 0);
  }

  bool reaches(int t, int row) const { return lo[t] <= row && row < hi[t]; }

  // alone and near over the active rows [row_lo, row_hi), from lo and hi.
  void plan(int row_lo, int row_hi) {
    std::fill(count.begin() + row_lo, count.begin() + row_hi, 0);
    for (std::size_t t = 0; t < lo.size(); ++t) {
      for (int r = std::max(lo[t], row_lo); r < std::min(hi[t], row_hi); ++r) ++count[r];
    }
    for (int r = row_lo; r < row_hi; ++r) {
      const int top = std::min(r + 3, row_hi);  // rows r, r + 1, r + 2: a stencil based at r
      bool shared_near = false, one = true;
      for (int k = std::max(r - 2, row_lo); k < top; ++k) shared_near |= count[k] > 1;
      for (int k = r; k < top; ++k) one &= count[k] <= 1;
      near[r] = shared_near;
      alone[r] = one;
    }
  }
};

}  // namespace compaction
