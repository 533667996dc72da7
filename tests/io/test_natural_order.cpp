// io::naturalLess, the order of a folder's scans: shuffled names sort back to the order people
// number them, and it is a strict weak order.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "ndtom_io/natural_order.h"

using ndtom::io::naturalLess;

TEST(NaturalOrder, NumbersCompareByValue) {
  const std::vector<std::string> expected = {"full0.pcd",  "full1.pcd",   "full2.pcd",
                                             "full9.pcd",  "full10.pcd",  "full11.pcd",
                                             "full59.pcd", "full100.pcd", "scan_a.pcd"};
  std::vector<std::string> names = expected;
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(names.begin(), names.end(), rng);
    std::sort(names.begin(), names.end(), naturalLess);
    EXPECT_EQ(names, expected);
  }
  // A strict weak order: irreflexive, and zero padding does not make names equal.
  EXPECT_FALSE(naturalLess("a10", "a10"));
  EXPECT_NE(naturalLess("a007", "a7"), naturalLess("a7", "a007"));
  EXPECT_TRUE(naturalLess("a", "a0"));
}
