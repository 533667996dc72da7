// Progress lines: the time left and the rates against hand-computed values, the text of a
// line, and how many lines a task writes to a log (stderr captured, so not a terminal).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "ndtom_apps/progress.h"

using ndtom::apps::Progress;
using ndtom::apps::ProgressState;
using ndtom::apps::progressText;

namespace {

ProgressState stateOf(size_t done, size_t total, double elapsed, size_t points = 0) {
  ProgressState s;
  s.done = done;
  s.total = total;
  s.points = points;
  s.elapsed = s.rate_seconds = elapsed;
  return s;
}

size_t linesOf(const std::string& text) {
  return size_t(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

TEST(ProgressState, TimeLeftAtThePaceSoFar) {
  EXPECT_DOUBLE_EQ(stateOf(10, 40, 5.0).secondsLeft(), 15.0);  // 0.5 s per step, 30 to go
  EXPECT_DOUBLE_EQ(stateOf(1, 3, 2.0).secondsLeft(), 4.0);
}

TEST(ProgressState, NoTimeLeftBeforeTheFirstStepOrOnceDone) {
  EXPECT_EQ(stateOf(0, 40, 5.0).secondsLeft(), 0.0);  // no pace yet
  EXPECT_EQ(stateOf(40, 40, 5.0).secondsLeft(), 0.0);
  EXPECT_EQ(stateOf(41, 40, 5.0).secondsLeft(), 0.0);  // more than announced: no wrap-around
  EXPECT_EQ(stateOf(0, 0, 0.0).secondsLeft(), 0.0);
}

TEST(ProgressState, RatesOverTheTimedSecondsOnly) {
  ProgressState s = stateOf(10, 40, 8.0, 3'000'000);
  s.rate_seconds = 2.0;  // e.g. insertion alone, of 8 s in all
  EXPECT_DOUBLE_EQ(s.stepsPerSecond(), 5.0);
  EXPECT_DOUBLE_EQ(s.pointsPerSecond(), 1.5e6);
  EXPECT_DOUBLE_EQ(s.secondsLeft(), 24.0);  // the time left stays on wall time
  s.rate_seconds = 0;
  EXPECT_EQ(s.stepsPerSecond(), 0.0);
  EXPECT_EQ(s.pointsPerSecond(), 0.0);
}

TEST(ProgressText, LineWithLabelRateAndTimeLeft) {
  EXPECT_EQ(progressText("pass 2/3", "scans", stateOf(12, 60, 6.0), false),
            "pass 2/3: 12/60 scans, 2.00 scans/s, 24 s left");
  EXPECT_EQ(progressText("", "clouds", stateOf(2, 4, 1.0), false),
            "2/4 clouds, 2.00 clouds/s, 1 s left");
}

TEST(ProgressText, FinalLineGivesTheTotalTime) {
  EXPECT_EQ(progressText("fig1 tum", "scans", stateOf(3, 3, 6.04), true),
            "fig1 tum: 3/3 scans, 0.50 scans/s, done in 6.0 s");
}

TEST(ProgressText, PointsRateInMillions) {
  EXPECT_EQ(progressText("", "scans", stateOf(2, 4, 2.0, 3'000'000), false),
            "2/4 scans, 1.00 scans/s, 1.50 Mpoints/s, 2 s left");
}

TEST(ProgressText, BarFilledInProportionAndNeverBeyondItsWidth) {
  EXPECT_EQ(progressText("", "scans", stateOf(15, 60, 1.0), false, 20).substr(0, 23),
            "[#####...............] ");
  EXPECT_EQ(progressText("", "scans", stateOf(70, 60, 1.0), true, 4).substr(0, 7), "[####] ");
  EXPECT_EQ(progressText("", "scans", stateOf(0, 0, 0.0), true, 4).substr(0, 7), "[####] ");
}

TEST(Progress, LogGetsALineAtEveryTenthAndOneFinalLine) {
  testing::internal::CaptureStderr();
  Progress progress;  // stderr is a file now: plain lines
  progress.start("sweep", 100, "resolutions");
  for (size_t i = 1; i <= 100; ++i) progress.update(i);
  progress.finish();  // already written at 100/100: nothing more
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_EQ(linesOf(out), 11u) << out;  // tenths 0 to 9, then the final line
  EXPECT_EQ(out.find("sweep: 1/100 resolutions"), 0u) << out;
  EXPECT_NE(out.find("sweep: 100/100 resolutions, "), std::string::npos) << out;
  EXPECT_NE(out.find("done in"), std::string::npos) << out;
  EXPECT_EQ(out.find('\r'), std::string::npos) << out;
}

TEST(Progress, FinishWritesTheFinalLineWhenFewerStepsCame) {
  testing::internal::CaptureStderr();
  Progress progress;
  progress.start("pass 1/2", 5);
  progress.update(1, 1000);
  progress.update(2, 2000);
  progress.finish();
  progress.finish();
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_EQ(linesOf(out), 3u) << out;
  EXPECT_NE(out.find("pass 1/2: 2/5 scans, "), std::string::npos) << out;
  EXPECT_EQ(out.find("done in"), out.rfind("done in")) << out;
}

TEST(Progress, QuietWritesNothing) {
  testing::internal::CaptureStderr();
  Progress progress(false);
  progress.start("run 1/1", 3);
  for (size_t i = 1; i <= 3; ++i) progress.update(i, 10 * i, 0.1 * double(i));
  progress.finish();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}
