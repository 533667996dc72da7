// NdtMap::extractBlocks and extractBlockRange (the out-of-core build's tiles): the range form
// takes exactly what the predicate form takes, by either of its two paths; copyBlocks (the
// online mapper's registration target) copies what extractBlocks would move.
#include <gtest/gtest.h>

#include <random>
#include <utility>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/scale/block_moves.h"
#include "support/map_equality.h"

namespace {

using namespace ndtom;

// The range form looks blocks up one by one when the range is smaller than the map, and visits
// every block otherwise: both must take what the predicate form takes, nothing more.
TEST(ExtractBlocks, RangeTakesWhatThePredicateTakes) {
  NdtMap map;
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> coord(-60, 60);
  for (int i = 0; i < 3000; ++i) {
    const CellStats stats = CellStats::fromPoints(
        {Eigen::Vector3d(0.01 * (i % 7), 0, 0.02), {-0.01, 0.02, 0}, {0, -0.02, 0.01}});
    if (i % 3) map.setCell({coord(rng), coord(rng), coord(rng)}, float(i % 5) - 2.0f, {});
    else map.setCell({coord(rng), coord(rng), coord(rng)}, 1.5f, stats);
  }
  size_t blocks = 0;
  map.forEachBlock([&](const CellIndex&) { ++blocks; });
  ASSERT_GT(blocks, 500u);
  ASSERT_LT(blocks, 2601u);  // the ranges below marked "visited" are larger than the map
  const std::vector<std::pair<CellIndex, CellIndex>> ranges = {
      {{0, 0, 0}, {1, 1, 1}},        // 8 blocks: looked up
      {{-3, -2, 0}, {2, 3, 1}},      // 72: looked up
      {{-8, -8, -8}, {8, 8, 8}},     // more than the map holds: visited
      {{-8, -8, -8}, {8, 8, 0}},     // 2,601, more than the map holds: visited, blocks on top
      {{2, 2, 2}, {1, 5, 5}},        // empty
      {{100, 100, 100}, {101, 101, 101}}};  // nothing there
  for (const auto& [lo, hi] : ranges) {
    NdtMap by_range = map, by_predicate = map;
    const NdtMap taken = ndtom::extractBlockRange(by_range, lo, hi);
    const NdtMap expected = ndtom::extractBlocks(by_predicate, [&](const CellIndex& b) {
      return b.x >= lo.x && b.x <= hi.x && b.y >= lo.y && b.y <= hi.y && b.z >= lo.z && b.z <= hi.z;
    });
    ndtom::testing::expectBitIdentical(taken, expected);
    ndtom::testing::expectBitIdentical(by_range, by_predicate);
    EXPECT_EQ(taken.numCells() + by_range.numCells(), map.numCells());
  }
}

// A copy of the blocks is what moving them out gives, bit for bit, its memory counted the
// same, and the source keeps every block.
TEST(CopyBlocks, CopiesWhatExtractionWouldMoveAndLeavesTheMap) {
  NdtMap map;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> coord(-40, 40);
  for (int i = 0; i < 2000; ++i) {
    const CellStats stats = CellStats::fromPoints(
        {Eigen::Vector3d(0.01 * (i % 5), 0, 0.02), {-0.01, 0.02, 0}, {0, -0.02, 0.01}});
    map.setCell({coord(rng), coord(rng), coord(rng)}, i % 2 ? 1.0f : -0.5f,
                i % 2 ? stats : CellStats{});
  }
  const NdtMap before = map;
  const auto take = [](const CellIndex& b) { return b.x >= 0 && b.y < 2; };
  const NdtMap copy = ndtom::copyBlocks(map, take);
  ndtom::testing::expectBitIdentical(map, before);
  NdtMap moved_from = map;
  const NdtMap moved = ndtom::extractBlocks(moved_from, take);
  ASSERT_GT(moved.numCells(), 100u);
  ndtom::testing::expectBitIdentical(copy, moved);
  EXPECT_EQ(copy.memoryBytes(), copy.memoryBytesCounted());
  EXPECT_NE(copy.revision(), map.revision());
  // Only the blocks with statistics: every cell with statistics, no block without.
  const NdtMap with_stats = ndtom::copyBlocks(map, take, /*statistics_only=*/true);
  size_t stats_cells = 0, stats_cells_copied = 0;
  copy.forEachCell([&](const CellView& c) { stats_cells += c.stats != nullptr; });
  with_stats.forEachCell([&](const CellView& c) { stats_cells_copied += c.stats != nullptr; });
  EXPECT_EQ(stats_cells_copied, stats_cells);
  EXPECT_GT(stats_cells, 50u);
  EXPECT_LT(with_stats.numBlocks(), copy.numBlocks());
  with_stats.forEachBlock([&](const CellIndex& b) {
    bool any = false;
    with_stats.forEachCell([&](const CellView& c) {
      any = any || (blockOf(c.index) == b && c.stats != nullptr);
    });
    EXPECT_TRUE(any);
  });
}

}  // namespace
