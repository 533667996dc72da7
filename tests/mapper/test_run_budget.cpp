// The memory budget of a mapping run when --memory-budget is not given: 4 x the input's size
// on disk, at least the library's default, at most half the memory available. The rule
// against hand-computed cases; the input's size against files written here (sparse ones for
// large sizes); the programs' summaries against the rule.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mapper_run.h"
#include "ndtom/map/memory_budget.h"
#include "ndtom_apps/run_budget.h"

using namespace mapper_test;
using ndtom::mapper::budgetForInput;

namespace {

constexpr uint64_t kMB = 1000000;

void writeBytes(const fs::path& path, size_t bytes) {
  std::ofstream(path, std::ios::binary) << std::string(bytes, 'x');
}

}  // namespace

TEST(RunBudget, FourTimesTheInputBetweenTheDefaultAndHalfOfWhatIsAvailable) {
  const uint64_t floor = 512 * kMB;
  EXPECT_EQ(budgetForInput(10 * kMB, 24000 * kMB, floor), floor) << "small inputs keep the default";
  EXPECT_EQ(budgetForInput(287 * kMB, 24000 * kMB, floor), 1148 * kMB) << "1 km of city";
  EXPECT_EQ(budgetForInput(5000 * kMB, 24000 * kMB, floor), 12000 * kMB) << "half of 24 GB";
  EXPECT_EQ(budgetForInput(5000 * kMB, 600 * kMB, floor), floor) << "never below the default";
  EXPECT_EQ(budgetForInput(5000 * kMB, 0, floor), 20000 * kMB) << "available unknown";
  EXPECT_EQ(budgetForInput(UINT64_MAX / 2, 0, floor), UINT64_MAX) << "saturates";
}

TEST(RunBudget, TheInputsSizeIsItsFilesUnderTheFolder) {
  TempDir dir;
  fs::create_directories(dir / "in" / "depth");
  writeBytes(dir / "in" / "a.pcd", 1000);
  writeBytes(dir / "in" / "depth" / "b.png", 234);
  fs::create_symlink(dir / "in" / "a.pcd", dir / "in" / "c.pcd");  // a linked scan counts
  EXPECT_EQ(ndtom::mapper::inputBytes((dir / "in").string()), 2234u);
  EXPECT_EQ(ndtom::mapper::inputBytes((dir / "in" / "a.pcd").string()), 1000u);
  EXPECT_EQ(ndtom::mapper::inputBytes((dir / "missing").string()), 0u);
  // A large input, without writing it: a sparse file.
  fs::resize_file(dir / "in" / "depth" / "b.png", 300 * kMB);
  EXPECT_EQ(ndtom::mapper::inputBytes((dir / "in").string()), 300 * kMB + 2000);
}

TEST(RunBudget, AppliedUnlessTheCommandLineGivesOne) {
  TempDir dir;
  fs::create_directories(dir / "in");
  writeBytes(dir / "in" / "a.pcd", 10);
  fs::resize_file(dir / "in" / "a.pcd", 200 * kMB);
  ndtom::mapper::InsertionSettings settings;
  ndtom::mapper::InsertionOptions options;
  const auto budget = ndtom::mapper::applyRunBudget(options, settings, (dir / "in").string());
  EXPECT_FALSE(budget.given);
  EXPECT_EQ(budget.input_bytes, 200 * kMB);
  EXPECT_EQ(budget.bytes,
            budgetForInput(200 * kMB, budget.available_bytes, ndtom::defaultMemoryBudget()));
  EXPECT_EQ(options.scan.memory_budget, budget.bytes);
  if (budget.available_bytes > 2 * 800 * kMB && ndtom::defaultMemoryBudget() < 800 * kMB) {
    EXPECT_EQ(budget.bytes, 800 * kMB);
  }
  EXPECT_NE(budget.rule.find("4 x the input's 200 MB"), std::string::npos) << budget.rule;

  settings.overrides.push_back({"memory_budget", "300"});
  ndtom::mapper::InsertionOptions given;
  given.scan.memory_budget = 300 * kMB;
  const auto kept = ndtom::mapper::applyRunBudget(given, settings, (dir / "in").string());
  EXPECT_TRUE(kept.given);
  EXPECT_EQ(given.scan.memory_budget, 300 * kMB);
  EXPECT_EQ(kept.rule, "--memory-budget");
}

TEST(RunBudget, NdtomMapSaysWhichBudgetItRanUnder) {
  TempDir dir;
  const auto summaryOf = [&](const std::string& stem, const std::string& args) {
    const ProgramRun run = runMapper(quoted(kLidar) + " -o " + quoted((dir / stem).string()) +
                                         " --max-scans 2 --no-pictures " + args,
                                     dir);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("budget"), std::string::npos) << run.out;
    return readText(dir / (stem + ".summary.json"));
  };
  // The shipped scans are a few MB: the default.
  const std::string small = summaryOf("small", "");
  EXPECT_EQ(jsonNumber(small, "budget_bytes"), double(ndtom::defaultMemoryBudget()));
  EXPECT_EQ(jsonNumber(small, "input_bytes"), double(ndtom::mapper::inputBytes(kLidar)));
  const std::string given = summaryOf("given", "--memory-budget 300");
  EXPECT_EQ(jsonNumber(given, "budget_bytes"), 300e6);
  EXPECT_NE(given.find("\"budget_rule\": \"--memory-budget\""), std::string::npos) << given;
}

TEST(RunBudget, AnInputTooLargeForTheMachineIsMappedOutOfCore) {
  const uint64_t available = ndtom::mapper::availableMemoryBytes();
  if (available == 0) GTEST_SKIP() << "no /proc/meminfo";
  // The shipped scans, and beside them a sparse file as large as the memory available: the
  // input's size says the map will not fit (the scans themselves are a few MB).
  TempDir dir;
  const fs::path input = dir / "scans";
  fs::create_directories(input);
  for (const auto& entry : fs::directory_iterator(kLidar))
    fs::create_symlink(entry.path(), input / entry.path().filename());
  writeBytes(input / "padding.bin", 1);
  fs::resize_file(input / "padding.bin", available);
  const ProgramRun run = runMapper(
      quoted(input.string()) + " -o " + quoted((dir / "big").string()) + " --max-scans 2", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("building out of core"), std::string::npos) << run.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "big.ndtomtiles"));
  EXPECT_FALSE(fs::exists(dir / "big.ndtom"));
  const std::string summary = readText(dir / "big.summary.json");
  EXPECT_GT(jsonNumber(summary, "resident_budget_bytes"), 0);
  // Asked for a budget, it builds in memory.
  const ProgramRun asked =
      runMapper(quoted(input.string()) + " -o " + quoted((dir / "asked").string()) +
                    " --max-scans 2 --no-pictures --memory-budget 600",
                dir);
  ASSERT_EQ(asked.exit_code, 0) << asked.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "asked.ndtom"));
  EXPECT_EQ(asked.err.find("out of core"), std::string::npos) << asked.err;
}
