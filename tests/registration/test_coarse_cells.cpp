// A pyramid level's coarse cells, found block by block, against a brute-force set of every
// fine cell divided by the factor; the same for any thread count.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "registration/coarse_cells.h"

using namespace ndtom;
using namespace ndtom::registration;

namespace {

// Fine blocks on both sides of zero, some full, most sparse, a few far apart.
std::vector<BlockCells> randomBlocks(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> coordinate(-9, 9);
  std::set<CellIndex> keys;
  while (keys.size() < 400) keys.insert({coordinate(rng), coordinate(rng), coordinate(rng) / 3});
  keys.insert({-1000, 77, -3});
  keys.insert({1 << 20, -(1 << 20), 5});
  std::vector<BlockCells> blocks;
  for (const CellIndex& key : keys) {
    BlockCells b{key, {}};
    const int kind = int(rng() % 4);
    for (uint64_t& word : b.cells)
      word = kind == 0 ? ~uint64_t(0) : (uint64_t(rng()) << 32 | rng()) & (uint64_t(rng()) << 32 | rng()) & rng();
    blocks.push_back(b);
  }
  std::shuffle(blocks.begin(), blocks.end(), rng);  // as a hash map lists them
  return blocks;
}

std::vector<CellIndex> bruteForce(const std::vector<BlockCells>& fine, int factor,
                                  const std::function<bool(const CellIndex&)>& member) {
  std::set<CellIndex, decltype(&inBlockOrder)> cells(&inBlockOrder);
  for (const BlockCells& b : fine) {
    if (member && !member(b.block)) continue;
    for (int offset = 0; offset < kBlockCells; ++offset)
      if (b.cells[size_t(offset) / 64] >> (offset % 64) & 1)
        cells.insert(cellwiseFloorDiv(cellInBlock(b.block, offset), factor));
  }
  return {cells.begin(), cells.end()};
}

}  // namespace

TEST(CoarseCells, BlocksOverAreTheFineCellsDividedByTheFactor) {
  const std::vector<BlockCells> fine = randomBlocks(7);
  const NdtMap map(MapOptions{});  // only its resolution is read here
  const std::function<bool(const CellIndex&)> odd_x = [](const CellIndex& b) { return b.x % 2 != 0; };
  WorkerPool pool;
  for (const int factor : {1, 2, 3, 4, 5, 8, 16, 40})
    for (const bool members_only : {false, true}) {
      const CoarseCells coarse(map, factor, odd_x);
      const std::vector<CellIndex> want = bruteForce(fine, factor, members_only ? odd_x : nullptr);
      ASSERT_GT(want.size(), factor >= 16 ? 10u : 100u);
      for (const size_t threads : {1, 2, 3, 7}) {
        const Threads t{pool, threads};
        const std::string what = "factor " + std::to_string(factor) + ", " +
                                 std::to_string(threads) + " threads";
        EXPECT_EQ(coarse.cellsOver(fine, members_only, t), want) << what;
        const std::vector<BlockCells> blocks = coarse.blocksOver(fine, members_only, t);
        size_t cells = 0;
        for (size_t i = 0; i < blocks.size(); ++i) {
          if (i > 0) EXPECT_LT(blocks[i - 1].block, blocks[i].block) << what;
          size_t here = 0;
          for (const uint64_t word : blocks[i].cells) here += size_t(__builtin_popcountll(word));
          EXPECT_GT(here, 0u) << what << ": no empty blocks";
          cells += here;
        }
        EXPECT_EQ(cells, want.size()) << what;
      }
    }
}

TEST(CoarseCells, NoFineCellsNoCoarseOnes) {
  const NdtMap map(MapOptions{});
  WorkerPool pool;
  const CoarseCells coarse(map, 4, {});
  EXPECT_TRUE(coarse.blocksOver({}, false, {pool, 3}).empty());
  EXPECT_TRUE(coarse.blocksOver({BlockCells{{1, 2, 3}, {}}}, false, {pool, 1}).empty());
  EXPECT_TRUE(coarse.statsCells().empty());
}
