// The programs' clocks against the standard clocks around them: wall time since a start, and
// CPU time of the process and of the calling thread, which a busy loop advances.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "ndtom_apps/process_clock.h"

using namespace ndtom::apps;

TEST(ProcessClock, SecondsSinceIsTheSteadyClocksSpan) {
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto before = std::chrono::steady_clock::now();
  const double seconds = secondsSince(start);
  const auto after = std::chrono::steady_clock::now();
  EXPECT_GE(seconds, std::chrono::duration<double>(before - start).count());
  EXPECT_LE(seconds, std::chrono::duration<double>(after - start).count());
}

TEST(ProcessClock, CpuTimeAdvancesWithWork) {
  const double process = processCpuSeconds(), thread = threadCpuSeconds();
  volatile double sink = 0;
  const auto start = std::chrono::steady_clock::now();
  while (secondsSince(start) < 0.05) sink = sink + 1;
  EXPECT_GT(threadCpuSeconds(), thread);
  EXPECT_GT(processCpuSeconds(), process);
  // This thread's time is part of the process's.
  EXPECT_GE(processCpuSeconds() - process, threadCpuSeconds() - thread - 1e-3);
}
