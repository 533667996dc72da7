// main()'s error handling: exit status 2 for a bad command line, 1 for other failures and for
// output the standard output did not take, the body's own status otherwise; one line
// "program: message" on stderr (captured: no terminal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>

#include "ndtom_apps/option_values.h"
#include "ndtom_apps/run_program.h"

using ndtom::apps::oneLineMessage;
using ndtom::apps::runProgram;
using ndtom::apps::UsageError;

TEST(RunProgram, ReturnsTheBodysStatus) {
  testing::internal::CaptureStderr();
  EXPECT_EQ(runProgram("prog", [] { return 0; }), 0);
  EXPECT_EQ(runProgram("prog", [] { return 3; }), 3);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(RunProgram, UsageErrorIsStatusTwo) {
  testing::internal::CaptureStderr();
  const int status = runProgram("ndtom-x", []() -> int { throw UsageError("--n: missing value"); });
  EXPECT_EQ(status, 2);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "ndtom-x: --n: missing value\n");
}

TEST(RunProgram, OtherFailuresAreStatusOneOnOneLine) {
  testing::internal::CaptureStderr();
  const int status = runProgram("ndtom-x", []() -> int {
    throw std::runtime_error(
        "==== MRPT exception ====\nMessage: cannot open a.rawlog\nat f.cpp:3\n");
  });
  EXPECT_EQ(status, 1);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "ndtom-x: cannot open a.rawlog\n");
}

TEST(RunProgram, OutOfMemorySaysSo) {
  testing::internal::CaptureStderr();
  const int status = runProgram("ndtom-x", []() -> int { throw std::bad_alloc(); });
  EXPECT_EQ(status, 1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err.rfind("ndtom-x: out of memory: ", 0), 0u) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(OneLineMessage, PlainMessagesStayAsTheyAre) {
  EXPECT_EQ(oneLineMessage(std::runtime_error("plain")), "plain");
  EXPECT_EQ(oneLineMessage(std::runtime_error("first\nsecond")), "first");
}

// Output that never reached the file (a full disk behind a redirection) fails the run.
TEST(RunProgramDeathTest, UnwrittenStandardOutputIsStatusOne) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  EXPECT_EXIT(
      {
        if (!std::freopen("/dev/full", "w", stdout)) std::exit(99);
        std::exit(runProgram("ndtom-x", [] {
          std::printf("a report\n");
          return 0;
        }));
      },
      testing::ExitedWithCode(1), "ndtom-x: cannot write the standard output: No space left");
}
