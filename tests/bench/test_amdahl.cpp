// The Amdahl prediction of ndtom-bench against values worked out by hand.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "amdahl.h"

using ndtom::bench::amdahlSpeedup;
using ndtom::bench::parallelFraction;

TEST(Amdahl, MatchesHandComputedSpeedups) {
  // p = 0.9: 1 / (0.1 + 0.9/n).
  EXPECT_NEAR(amdahlSpeedup(0.9, 2), 1 / 0.55, 1e-12);      // 1.8182
  EXPECT_NEAR(amdahlSpeedup(0.9, 4), 1 / 0.325, 1e-12);     // 3.0769
  EXPECT_NEAR(amdahlSpeedup(0.9, 16), 1 / 0.15625, 1e-12);  // 6.4
  // p = 0.984 (an insertion's): 1 / (0.016 + 0.0615) = 12.903.
  EXPECT_NEAR(amdahlSpeedup(0.984, 16), 12.903225806451612, 1e-9);
  EXPECT_NEAR(amdahlSpeedup(0.5, 8), 1 / 0.5625, 1e-12);  // 1.7778
}

TEST(Amdahl, SpinningWorkersCpu) {
  // 16 threads busy (working or spinning) for the whole of S(16)'s wall time, worked out by
  // hand: p = 0.98 -> 16 * 0.02 + 0.98 = 1.30; p = 0.9 -> 16 * 0.1 + 0.9 = 2.5.
  EXPECT_NEAR(ndtom::bench::spinningCpuRatio(0.98, 16), 1.30, 1e-12);
  EXPECT_NEAR(ndtom::bench::spinningCpuRatio(0.9, 16), 2.5, 1e-12);
  EXPECT_DOUBLE_EQ(ndtom::bench::spinningCpuRatio(1, 16), 1);   // no serial stretch: no waste
  EXPECT_DOUBLE_EQ(ndtom::bench::spinningCpuRatio(0, 16), 16);  // all serial: 15 spin
  EXPECT_DOUBLE_EQ(ndtom::bench::spinningCpuRatio(0.7, 1), 1);
  EXPECT_THROW(ndtom::bench::spinningCpuRatio(1.5, 16), std::invalid_argument);
}

TEST(Amdahl, EdgeCases) {
  for (double n : {1.0, 2.0, 16.0, 1e6}) {
    EXPECT_DOUBLE_EQ(amdahlSpeedup(0, n), 1);  // all serial: no gain
    EXPECT_DOUBLE_EQ(amdahlSpeedup(1, n), n);  // all parallel: linear
    EXPECT_DOUBLE_EQ(amdahlSpeedup(0.7, 1), 1);
  }
  // More threads never predict less, and never more than 1 / (1 - p).
  double last = 1;
  for (int n = 1; n <= 64; ++n) {
    const double s = amdahlSpeedup(0.95, n);
    EXPECT_GE(s, last);
    EXPECT_LT(s, 20 + 1e-9);
    last = s;
  }
}

TEST(Amdahl, RejectsInvalidInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double p : {-0.01, 1.01, nan, inf})
    EXPECT_THROW(amdahlSpeedup(p, 4), std::invalid_argument) << p;
  for (double n : {0.0, 0.5, -2.0, nan, inf})
    EXPECT_THROW(amdahlSpeedup(0.5, n), std::invalid_argument) << n;
}

TEST(Amdahl, ParallelFractionOfAOneThreadRun) {
  EXPECT_DOUBLE_EQ(parallelFraction(9.6, 12), 0.8);
  EXPECT_DOUBLE_EQ(parallelFraction(0, 3), 0);
  EXPECT_DOUBLE_EQ(parallelFraction(3.0000001, 3), 1);  // clocks read apart: clamped
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(parallelFraction(1, 0), std::invalid_argument);
  EXPECT_THROW(parallelFraction(-1, 3), std::invalid_argument);
  EXPECT_THROW(parallelFraction(nan, 3), std::invalid_argument);
  EXPECT_THROW(parallelFraction(1, nan), std::invalid_argument);
}
