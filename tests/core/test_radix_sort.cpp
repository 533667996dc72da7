// The ray ends' radix sort (private header) against std::stable_sort, for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "radix_sort.h"

namespace {

struct Item {
  uint64_t key;
  uint32_t index;  ///< input position: shows whether equal keys kept their order
  bool operator==(const Item& o) const { return key == o.key && index == o.index; }
};

std::vector<Item> randomItems(size_t n, int key_bits, uint64_t distinct, unsigned seed) {
  std::mt19937_64 rng(seed);
  const uint64_t limit = key_bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << key_bits) - 1;
  std::vector<uint64_t> keys(distinct);  // few distinct keys: long runs of equal ones
  for (uint64_t& k : keys) k = std::uniform_int_distribution<uint64_t>(0, limit)(rng);
  std::vector<Item> items(n);
  for (size_t i = 0; i < n; ++i) items[i] = {keys[rng() % distinct], uint32_t(i)};
  return items;
}

TEST(RadixSort, MatchesStableSortForAnyThreadCountAndKeyWidth) {
  ndtom::WorkerPool pool;
  for (const int key_bits : {1, 9, 13, 14, 26, 40})
    for (const size_t threads : {1, 2, 3, 7}) {
      std::vector<Item> items = randomItems(20000, key_bits, 3000, unsigned(key_bits)), buffer;
      std::vector<Item> expected = items;
      std::stable_sort(expected.begin(), expected.end(),
                       [](const Item& a, const Item& b) { return a.key < b.key; });
      ndtom::radixSortByKey(items, buffer, key_bits, pool, threads);
      EXPECT_EQ(items, expected) << key_bits << " key bits, " << threads << " threads";
    }
}

TEST(RadixSort, FewerItemsThanThreadsAndEmptyInput) {
  ndtom::WorkerPool pool;
  std::vector<Item> items{{5, 0}, {1, 1}, {5, 2}}, buffer;
  ndtom::radixSortByKey(items, buffer, 3, pool, 8);
  EXPECT_EQ(items, (std::vector<Item>{{1, 1}, {5, 0}, {5, 2}}));
  items.clear();
  ndtom::radixSortByKey(items, buffer, 3, pool, 2);
  EXPECT_TRUE(items.empty());
}

}  // namespace
