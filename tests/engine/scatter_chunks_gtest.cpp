// How P2G cuts the particles into chunks of two colours (engine/src/scatter_chunks.hpp): the
// chunks cover the blocks once, in order; no two chunks of one colour reach a common row, for
// particles in their lattice order, a little out of it, or in none; and the cut depends on the
// rows alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>

#include "scatter_chunks.hpp"
#include "splitmix64.hpp"

namespace compaction {
namespace {

// Rows of a block whose particles lie around row `row`, `spread` rows deep.
void set_block(ScatterChunks& c, std::size_t b, int row, int spread) {
  c.block_lo[b] = row;
  c.block_hi[b] = row + spread + 3;  // a stencil covers three rows
}

// The cut covers blocks [0, blocks) once, in order, and chunks k and j >= k + 2 (the same
// colour, or any later one of the other) share no row.
void expect_valid_cut(const ScatterChunks& c, std::size_t blocks, const std::string& what) {
  if (blocks == 0) {
    EXPECT_EQ(c.count, 0u) << what;
    return;
  }
  ASSERT_GE(c.count, 1u) << what;
  ASSERT_EQ(c.start[0], 0u) << what;
  ASSERT_EQ(c.start[c.count], blocks) << what;
  for (std::size_t k = 0; k < c.count; ++k) ASSERT_LT(c.start[k], c.start[k + 1]) << what;
  for (std::size_t k = 0; k < c.count; ++k) {
    int hi = 0;
    for (std::size_t b = c.start[k]; b < c.start[k + 1]; ++b) hi = std::max(hi, c.block_hi[b]);
    for (std::size_t b = c.start[std::min(k + 2, c.count)]; b < blocks; ++b) {
      ASSERT_GE(c.block_lo[b], hi) << what << ": block " << b << " reaches chunk " << k;
    }
  }
}

TEST(ScatterChunksGtest, BlocksInLatticeOrderMakeChunksOfTheTargetSize) {
  ScatterChunks c;
  const std::size_t blocks = 2716;  // 86 904 particles in blocks of 32
  c.fit(blocks * 32, 32);
  for (std::size_t b = 0; b < blocks; ++b) set_block(c, b, static_cast<int>(b / 4), 1);
  c.cut(blocks);
  expect_valid_cut(c, blocks, "lattice order");
  EXPECT_EQ(c.count, 64u);  // 43 blocks each (2716 / 64, rounded up), the last one 7
  EXPECT_EQ(c.start[1], 43u);
  EXPECT_EQ(c.start[63], 63u * 43);
}

// A block reaching twenty rows below its neighbours (a particle out of the lattice order) lies
// within reach of chunk 27 (blocks 1080-1119, up to row 283): chunk 28 grows from the target of
// 40 blocks to take it in, and the chunks after it keep the target.
TEST(ScatterChunksGtest, ABlockOutOfOrderLengthensAChunk) {
  ScatterChunks c;
  const std::size_t blocks = 2560;
  c.fit(blocks * 32, 32);
  for (std::size_t b = 0; b < blocks; ++b) set_block(c, b, static_cast<int>(b / 4), 1);
  set_block(c, 1200, 300 - 20, 21);
  c.cut(blocks);
  expect_valid_cut(c, blocks, "one block out of order");
  EXPECT_EQ(c.count, 63u);
  EXPECT_EQ(c.start[28], 28u * 40);
  EXPECT_EQ(c.start[29], 1201u);
  EXPECT_EQ(c.start[30], 1241u);
}

// Random rows, a few blocks in order, blocks in no order at all and none: always a valid cut,
// and the same cut for the same rows.
TEST(ScatterChunksGtest, AnyRowsGiveAValidCut) {
  ScatterChunks c, d;
  SplitMix64 rng(11);
  for (std::size_t blocks : {0u, 1u, 2u, 3u, 5u, 64u, 65u, 200u, 1000u}) {
    for (int disorder : {0, 3, 10, 1000}) {
      c.fit(blocks * 32, 32), d.fit(blocks * 32, 32);
      for (std::size_t b = 0; b < blocks; ++b) {
        const int jitter = static_cast<int>(rng.next() % (disorder + 1));
        set_block(c, b, static_cast<int>(b / 2) + jitter, static_cast<int>(rng.next() % 3));
        d.block_lo[b] = c.block_lo[b], d.block_hi[b] = c.block_hi[b];
      }
      c.cut(blocks), d.cut(blocks);
      const std::string what = std::to_string(blocks) + " blocks, disorder " +
                               std::to_string(disorder);
      expect_valid_cut(c, blocks, what);
      ASSERT_EQ(c.count, d.count) << what;
      for (std::size_t k = 0; k <= c.count; ++k) ASSERT_EQ(c.start[k], d.start[k]) << what;
    }
  }
}

// Blocks from the top down (the reverse of the lattice order): no block after the first
// chunk lies above it, so the rest is one chunk, scattered after the first by one thread.
TEST(ScatterChunksGtest, BlocksFromTheTopDownMakeTwoChunks) {
  ScatterChunks c;
  const std::size_t blocks = 500;
  c.fit(blocks * 32, 32);
  for (std::size_t b = 0; b < blocks; ++b) set_block(c, b, static_cast<int>(blocks - b), 1);
  c.cut(blocks);
  expect_valid_cut(c, blocks, "top down");
  EXPECT_EQ(c.count, 2u);
}

}  // namespace
}  // namespace compaction
