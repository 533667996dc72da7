// The ray ends' radix sort (private header) against std::stable_sort, for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "support/radix_sort.h"

namespace {

constexpr int kIndexBits = 20;  ///< low bits: the input position, shows whether ties kept order

std::vector<uint64_t> randomWords(size_t n, int key_bits, uint64_t distinct, unsigned seed) {
  std::mt19937_64 rng(seed);
  const uint64_t limit = (uint64_t(1) << key_bits) - 1;
  std::vector<uint64_t> keys(distinct);  // few distinct keys: long runs of equal ones
  for (uint64_t& k : keys) k = std::uniform_int_distribution<uint64_t>(0, limit)(rng);
  std::vector<uint64_t> words(n);
  for (size_t i = 0; i < n; ++i) words[i] = keys[rng() % distinct] << kIndexBits | i;
  return words;
}

TEST(RadixSort, MatchesStableSortForAnyThreadCountAndKeyWidth) {
  ndtom::WorkerPool pool;
  for (const int key_bits : {1, 9, 13, 14, 26, 40, 64 - kIndexBits})
    for (const size_t threads : {1, 2, 3, 7, 16}) {  // from 7, offsets by digit ranges
      std::vector<uint64_t> words = randomWords(20000, key_bits, 3000, unsigned(key_bits)), buffer;
      std::vector<uint64_t> expected = words;
      std::stable_sort(expected.begin(), expected.end(), [](uint64_t a, uint64_t b) {
        return a >> kIndexBits < b >> kIndexBits;
      });
      ndtom::radixSortByBits(words, buffer, kIndexBits, key_bits, pool, threads);
      EXPECT_EQ(words, expected) << key_bits << " key bits, " << threads << " threads";
    }
}

TEST(RadixSort, SortsOnlyTheGivenBits) {
  ndtom::WorkerPool pool;
  // Keys in bits 4-6; the low bits are out of order and must stay in input order per key.
  std::vector<uint64_t> words{5 << 4 | 9, 1 << 4 | 15, 5 << 4 | 2, 0 << 4 | 7}, buffer;
  ndtom::radixSortByBits(words, buffer, 4, 3, pool, 2);
  EXPECT_EQ(words, (std::vector<uint64_t>{0 << 4 | 7, 1 << 4 | 15, 5 << 4 | 9, 5 << 4 | 2}));
}

TEST(RadixSort, FewerItemsThanThreadsAndEmptyInput) {
  ndtom::WorkerPool pool;
  std::vector<uint64_t> words{5 << 2 | 0, 1 << 2 | 1, 5 << 2 | 2}, buffer;
  ndtom::radixSortByBits(words, buffer, 2, 3, pool, 8);
  EXPECT_EQ(words, (std::vector<uint64_t>{1 << 2 | 1, 5 << 2 | 0, 5 << 2 | 2}));
  words.clear();
  ndtom::radixSortByBits(words, buffer, 2, 3, pool, 2);
  EXPECT_TRUE(words.empty());
}

}  // namespace
