// apps::quantile against the definition: linear interpolation between the order statistics
// at q·(n−1), whatever the input order; no samples give 0. apps::percentile: the nearest rank.
#include <gtest/gtest.h>

#include "ndtom_apps/statistics.h"

using ndtom::apps::percentile;
using ndtom::apps::quantile;

TEST(Quantile, InterpolatesBetweenOrderStatistics) {
  const std::vector<double> shuffled = {7, 1, 5, 3, 9};  // sorted: 1 3 5 7 9
  EXPECT_DOUBLE_EQ(quantile(shuffled, 0.0), 1);
  EXPECT_DOUBLE_EQ(quantile(shuffled, 0.5), 5);
  EXPECT_DOUBLE_EQ(quantile(shuffled, 1.0), 9);
  EXPECT_DOUBLE_EQ(quantile(shuffled, 0.375), 4);   // position 1.5: halfway between 3 and 5
  EXPECT_DOUBLE_EQ(quantile(shuffled, 0.95), 8.6);  // position 3.8: 7 + 0.8·2
  EXPECT_DOUBLE_EQ(quantile({4, 2}, 0.5), 3);
}

TEST(Quantile, EdgeCases) {
  EXPECT_EQ(quantile({}, 0.5), 0);
  EXPECT_EQ(quantile({2.5}, 0.0), 2.5);
  EXPECT_EQ(quantile({2.5}, 0.95), 2.5);
}

TEST(Percentile, NearestRank) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);
  EXPECT_EQ(percentile(v, 0.5), 50);
  EXPECT_EQ(percentile(v, 0.95), 95);
  EXPECT_EQ(percentile(v, 1.0), 100);
  EXPECT_EQ(percentile({}, 0.5), 0);
}
