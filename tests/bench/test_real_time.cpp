// realTimeThresholds (Fig. 5's real-time line): for each system, the finest resolution from
// which on every coarser run stays within the scan period; worked out by hand below.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "real_time.h"

namespace {

using ndtom::bench::RunResult;

RunResult run(const std::string& label, double resolution, std::vector<double> ms) {
  RunResult r;
  r.dataset = "d";
  r.label = label;
  r.resolution = resolution;
  for (double v : ms) r.scan_seconds.push_back(v / 1e3);
  return r;
}

TEST(RealTime, FinestResolutionFromWhichAllCoarserRunsFit) {
  const std::vector<RunResult> runs = {
      run("a", 0.1, {300, 310, 290}),  // median 300
      run("a", 0.2, {90, 95, 80}),     // median 90: fits 100 ms, but 0.4 m does not
      run("a", 0.4, {120, 130, 110}),  // median 120
      run("a", 0.8, {50, 40, 60}),     // median 50
      run("b", 0.1, {99, 101, 100}),   // median 100: fits exactly
      run("b", 0.2, {10}),
      run("c", 0.8, {500}),
      run("other", 0.1, {1}),  // another dataset: not reported
  };
  std::vector<RunResult> with_other = runs;
  with_other.back().dataset = "e";
  const auto lines = ndtom::bench::realTimeThresholds(with_other, "d", 100);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "a: real time (<= 100 ms) from 0.8 m (50 ms)");
  EXPECT_EQ(lines[1], "b: real time (<= 100 ms) from 0.1 m (100 ms), the finest resolution run");
  EXPECT_EQ(lines[2], "c: not real time (<= 100 ms) at any resolution run");
  const auto relaxed = ndtom::bench::realTimeThresholds(with_other, "d", 300);
  EXPECT_EQ(relaxed[0], "a: real time (<= 300 ms) from 0.1 m (300 ms), the finest resolution run");
  EXPECT_TRUE(ndtom::bench::realTimeThresholds(with_other, "none", 100).empty());
}

}  // namespace
