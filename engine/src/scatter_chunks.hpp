// How P2G's threads share the particles (p2g.cpp).
//
// The particles are cut into chunks, contiguous in their order, with two colours, even and odd,
// such that no two chunks of one colour reach a common grid row: every particle after chunk
// k + 1 has its stencil above chunk k's rows. So the threads take a colour's chunks in turn
// and add straight into the grid, all the even chunks, then all the odd ones, and every node
// gets its particles' contributions in one order, whatever the number of threads: the results
// have the same bits on one thread as on several.
//
// The cut is made afresh each step from the particles' positions alone, a block of particles at
// a time (the scatter's blocks, so that a chunk is whole blocks): chunks of a target size, each
// made longer where needed until every later block lies above the chunk before it. The scene's
// lattice order keeps the particles nearly sorted by height (they move less than a cell per step
// and stay near their lattice neighbours), so the chunks rarely grow; particles far out of that
// order make longer chunks, and a column in no order at all one chunk, which one thread
// scatters.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace compaction {

struct ScatterChunks {
  // Chunks a cut aims at: enough for the threads to share the work evenly when each takes
  // chunks in turn, few enough that a chunk spans several rows.
  static constexpr std::size_t kChunks = 64;

  std::vector<int> block_lo, block_hi;  // block b's stencils reach rows [block_lo[b], block_hi[b])
  std::vector<int> above;               // above[b]: the lowest row that blocks b, b + 1, ... reach
  std::vector<std::size_t> start;       // chunk k: blocks [start[k], start[k + 1])
  std::size_t count = 0;                // chunks of the last cut

  // Makes room for n particles in blocks of `block` (allocates only when n grows).
  void fit(std::size_t n, std::size_t block) {
    const std::size_t blocks = (n + block - 1) / block;
    if (start.size() > blocks) return;
    block_lo.resize(blocks), block_hi.resize(blocks), above.resize(blocks);
    start.resize(blocks + 1);
  }

  // Cuts `blocks` blocks, whose rows are in block_lo and block_hi, into chunks of about
  // blocks / kChunks blocks: each chunk k + 1 grows until every block after it lies above
  // chunk k's rows.
  void cut(std::size_t blocks) {
    count = 0;
    if (blocks == 0) return;
    above[blocks - 1] = block_lo[blocks - 1];
    for (std::size_t b = blocks - 1; b-- > 0;) above[b] = std::min(block_lo[b], above[b + 1]);
    const std::size_t target = std::max<std::size_t>((blocks + kChunks - 1) / kChunks, 1);
    int hi_before = 0;  // the highest row the last chunk cut reaches
    for (std::size_t b = 0; b < blocks; ++count) {
      start[count] = b;
      std::size_t e = std::min(b + target, blocks);
      if (count > 0) {
        while (e < blocks && above[e] < hi_before) ++e;
      }
      hi_before = *std::max_element(block_hi.begin() + b, block_hi.begin() + e);
      b = e;
    }
    start[count] = blocks;
  }

  std::size_t begin(std::size_t k, std::size_t block) const { return start[k] * block; }
  std::size_t end(std::size_t k, std::size_t block, std::size_t n) const {
    return std::min(start[k + 1] * block, n);
  }
};

}  // namespace compaction
