// ndtom-eval end to end on the data shipped in the repository (3 TUM frames at decimation 4,
// 3 lidar scans): exit codes, the CSV columns, and values that must hold on any data.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
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
       {"fig1_tum.csv",       "fig1_tum.png",      "fig2_tum.csv",
        "fig1_lidar.csv",     "fig2_lidar.png",    "fig3_occupancy.csv",
        "fig3_occupancy.png", "conflicts_top.png", "conflicts_by_height.csv",
        "multires.csv",       "multires_fine.png", "multires_coarse.png",
        "sweep.csv",          "sweep_memory.png",  "raymodes.csv",
        "summary.csv",        "fig4a_ndtom.png",   "fig4b_recursive_conflicts.png",
        "fig4c_free.png",     "fig4d_coarse.png"})
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
  EXPECT_NE(missing.stderr_text.find("scripts/fetch-data.sh"), std::string::npos);
  EXPECT_EQ(std::count(missing.stderr_text.begin(), missing.stderr_text.end(), '\n'), 1);

  for (const char* bad_value : {"--clamp-max -1", "--clamp-min 0.5", "--min-travel 0",
                                "--min-turn 181", "--min-travel abc"}) {
    const ProgramRun r = runEval(bad_value, dir);
    EXPECT_EQ(r.exit_code, 2) << bad_value << ": " << r.stderr_text;
  }
  fs::remove_all(dir);
}

// The summary's value of `key`, or NaN.
double summaryValue(const fs::path& summary, const std::string& key) {
  const Csv csv = readCsv(summary);
  for (size_t i = 0; i < csv.rows.size(); ++i)
    if (csv.rows[i].at("key") == key) return csv.number(i, "value");
  return std::nan("");
}

// Scans at least `travel` m from the last kept one (the first is kept), from the KITTI lines.
size_t keptByTravel(const std::string& poses_path, double travel) {
  std::ifstream in(poses_path);
  std::string line;
  size_t kept = 0;
  double last[3] = {0, 0, 0};
  while (std::getline(in, line)) {
    std::istringstream s(line);
    double m[12];
    for (double& v : m) s >> v;
    if (!s) continue;
    const double t[3] = {m[3], m[7], m[11]};
    const double d = std::hypot(t[0] - last[0], t[1] - last[1], t[2] - last[2]);
    if (kept == 0 || d >= travel) {
      ++kept;
      std::copy(t, t + 3, last);
    }
  }
  return kept;
}

TEST(EvalProgram, ClampAndInsertionRule) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom_eval_opt_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string common = "--experiments mapping --lidar '" + kLidar + "' --lidar-scans 3 ";
  ASSERT_EQ(runEval(common + "--out '" + (dir / "a").string() + "'", dir).exit_code, 0);
  ASSERT_EQ(runEval(common + "--clamp-max 10 --out '" + (dir / "b").string() + "'", dir).exit_code,
            0);
  const Csv a = readCsv(dir / "a" / "fig3_occupancy.csv"),
            b = readCsv(dir / "b" / "fig3_occupancy.csv");
  // A higher upper clamp lets hit cells climb further: the mean rises above the default bound.
  EXPECT_LE(a.number(2, "mean_logodds_occupied"), 3.5);
  EXPECT_GT(b.number(2, "mean_logodds_occupied"), 3.5);
  EXPECT_LE(b.number(2, "mean_logodds_occupied"), 10.0);

  const ProgramRun gated = runEval("--experiments mapping --lidar '" + kLidar +
                                       "' --min-travel 0.01 --out '" + (dir / "c").string() + "'",
                                   dir);
  ASSERT_EQ(gated.exit_code, 0) << gated.stderr_text;
  const size_t expected = keptByTravel(kLidar + "/poses.txt", 0.01);
  ASSERT_GT(expected, 1u);
  ASSERT_LT(expected, 10u);
  EXPECT_EQ(summaryValue(dir / "c" / "summary.csv", "lidar_scans"), double(expected));
  EXPECT_EQ(summaryValue(dir / "c" / "summary.csv", "lidar_scans_read"), 10.0);
  EXPECT_EQ(readCsv(dir / "c" / "fig3_occupancy.csv").rows.size(), expected);
  fs::remove_all(dir);
}

}  // namespace
