// ndtom-eval end to end on the data shipped in the repository (3 TUM frames at decimation 4,
// 3 lidar scans): exit codes, the CSV columns, and values that must hold on any data.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "support/program_run.h"

namespace fs = std::filesystem;
using ndtom::testing::Csv;
using ndtom::testing::ProgramRun;
using ndtom::testing::readCsv;
using ndtom::testing::runProgram;

namespace {

const std::string kExe = NDTOM_EVAL_EXE;
const std::string kTum = std::string(NDTOM_SOURCE_DIR) + "/share/data/tum-fr2-pioneer-slam2";
const std::string kLidar = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

ProgramRun runEval(const std::string& args, const fs::path& dir) {
  return runProgram(kExe, args, dir);
}

fs::path g_out;  // output folder of the run under test

fs::path out(const std::string& file) {
  return g_out / file;
}

void checkFilesAndMessages(const ProgramRun& run) {
  ASSERT_EQ(run.exit_code, 0) << run.stderr_text;
  for (const char* file :
       {"fig1_tum.csv", "fig1_tum.png", "fig2_tum.csv", "fig1_lidar.csv", "fig2_lidar.png",
        "fig3_occupancy.csv", "fig3_occupancy.png", "conflicts_top.png", "conflicts_by_height.csv",
        "multires.csv", "multires_fine.png", "multires_coarse.png", "sweep.csv", "sweep_memory.png",
        "raymodes.csv", "summary.csv"})
    EXPECT_GT(fs::file_size(out(file)), 100u) << file;
  EXPECT_NE(run.stderr_text.find("3/3 scans"), std::string::npos);  // progress was shown
  EXPECT_NE(run.stdout_text.find("Summary"), std::string::npos);
}

void checkFig1() {
  for (const char* file : {"fig1_tum.csv", "fig1_lidar.csv"}) {
    const Csv csv = readCsv(out(file));
    EXPECT_EQ(csv.columns, (std::vector<std::string>{"cloud", "points_so_far", "batch_gaussians",
                                                     "recursive_gaussians", "ndtom_gaussians",
                                                     "er_gaussians", "similarity_recursive",
                                                     "similarity_ndtom", "similarity_er"}));
    ASSERT_EQ(csv.rows.size(), 3u) << file;
    for (size_t i = 0; i < csv.rows.size(); ++i) {
      EXPECT_EQ(csv.number(i, "recursive_gaussians"), csv.number(i, "batch_gaussians"));
      EXPECT_GT(csv.number(i, "batch_gaussians"), 100);
      EXPECT_NEAR(csv.number(i, "similarity_recursive"), 1.0, 1e-9) << file;
      for (const char* m : {"similarity_ndtom", "similarity_er"}) {
        EXPECT_GT(csv.number(i, m), 0.3) << file << " " << m;
        EXPECT_LE(csv.number(i, m), 1.0) << file << " " << m;
      }
    }
    // After the first cloud ER has refined nothing yet; later it trails Recursive NDT.
    EXPECT_LT(csv.number(2, "similarity_er"), csv.number(2, "similarity_recursive") - 0.01);
  }
}

void checkFig2AndFig3() {
  const Csv fig2 = readCsv(out("fig2_lidar.csv"));
  ASSERT_EQ(fig2.rows.size(), 3u);
  for (size_t i = 0; i < 3; ++i)
    for (const char* m : {"similarity_recursive", "similarity_ndtom", "similarity_er"}) {
      EXPECT_GT(fig2.number(i, m), 0.0);
      EXPECT_LE(fig2.number(i, m), 1.0);
    }
  const Csv fig3 = readCsv(out("fig3_occupancy.csv"));
  ASSERT_EQ(fig3.rows.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_GT(fig3.number(i, "mean_logodds_occupied"), 0.0);
    EXPECT_LE(fig3.number(i, "mean_logodds_occupied"), 3.5);  // the default clamp
    EXPECT_LT(fig3.number(i, "mean_logodds_empty"), 0.0);
    EXPECT_GE(fig3.number(i, "mean_logodds_empty"), -2.0);
    EXPECT_GE(fig3.number(i, "known_cells"),
              fig3.number(i, "occupied_cells") + fig3.number(i, "empty_cells"));
  }
}

void checkMultiResolution() {
  const Csv csv = readCsv(out("multires.csv"));
  ASSERT_EQ(csv.rows.size(), 6u);
  EXPECT_EQ(csv.rows[1].at("map"), "recursive_derived");
  EXPECT_EQ(csv.number(1, "cells_n_mismatch"), 0);
  EXPECT_LT(csv.number(1, "max_mean_diff_m"), 1e-9);
  EXPECT_NEAR(csv.number(1, "similarity_to_batch"), 1.0, 1e-9);
  EXPECT_EQ(csv.number(1, "gaussians"), csv.number(5, "gaussians"));  // batch_coarse
  EXPECT_LT(csv.number(1, "gaussians"), csv.number(0, "gaussians"));
}

void checkSweepAndRayModes() {
  const Csv sweep = readCsv(out("sweep.csv"));
  ASSERT_EQ(sweep.rows.size(), 2u);
  EXPECT_GT(sweep.number(0, "memory_ndtom_bytes"), sweep.number(1, "memory_ndtom_bytes"));
  EXPECT_NEAR(sweep.number(0, "similarity_recursive"), 1.0, 1e-9);
  const Csv modes = readCsv(out("raymodes.csv"));
  ASSERT_EQ(modes.rows.size(), 1u);
  EXPECT_GT(modes.number(0, "similarity_hit_cell_vs_per_point"), 0.5);
  EXPECT_LE(modes.number(0, "similarity_hit_cell_vs_per_point"), 1.0);
  EXPECT_LT(modes.number(0, "visits_ratio"), 1.0);  // fewer rays, fewer visits
  EXPECT_GE(modes.number(0, "occupancy_sign_differs_share"), 0.0);
  EXPECT_LT(modes.number(0, "occupancy_sign_differs_share"), 0.5);
}

// One run (about 3 s) checked from every side; the checks are separate functions so that a
// failure names the part that broke.
TEST(EvalProgram, EndToEndOnShippedData) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom_eval_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  g_out = dir / "out";
  const ProgramRun run = runEval(
      "--tum '" + kTum + "' --tum-frames 3 --tum-decimation 4 --lidar '" + kLidar +
          "' --lidar-scans 3 --consistency-scans 3 --sweep 0.4,0.8 --ray-mode-resolutions 0.4" +
          " --out '" + g_out.string() + "'",
      dir);
  checkFilesAndMessages(run);
  if (run.exit_code == 0) {
    checkFig1();
    checkFig2AndFig3();
    checkMultiResolution();
    checkSweepAndRayModes();
  }
  fs::remove_all(dir);
}

TEST(EvalProgram, HelpBadOptionAndMissingData) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom_eval_err_" + std::to_string(getpid()));
  fs::create_directories(dir);
  ProgramRun help = runEval("--help", dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.stdout_text.find("--experiments"), std::string::npos);

  ProgramRun bad = runEval("--sweep 0.1,abc", dir);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.stderr_text, "ndtom-eval: --sweep: not a number: 'abc'\n");

  ProgramRun missing = runEval("--experiments mapping --lidar '" + (dir / "nowhere").string() +
                                   "' --out '" + (dir / "out").string() + "'",
                               dir);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.stderr_text.find("no poses.txt"), std::string::npos);
  EXPECT_EQ(std::count(missing.stderr_text.begin(), missing.stderr_text.end(), '\n'), 1);
  fs::remove_all(dir);
}

}  // namespace
