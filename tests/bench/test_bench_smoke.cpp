// Smoke test of ndtom-bench on 2 shipped lidar scans at 0.8 m: the CSV and the summary have
// one row per system with sane positive numbers, NDT-OM's figures equal a map built here
// independently, and bad input fails with a one-line message. No timing thresholds.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace fs = std::filesystem;

namespace {

const std::string kData = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
constexpr double kResolution = 0.8, kMaxRange = 30.0;
constexpr int kScans = 2;

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string item; std::getline(s, item, sep);) out.push_back(item);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

/// Runs the benchmark program; returns its exit status, stdout and stderr in files of `dir`.
int runBench(const fs::path& dir, const std::string& args) {
  const std::string cmd = std::string(NDTOM_BENCH_EXE) + " " + args + " >" +
                          (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class BenchSmoke : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("ndtom-bench-smoke-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    status_ = runBench(dir_, "--dataset " + kData + " --scans 2 --resolutions 0.8 --threads 1 " +
                                 "--csv " + (dir_ / "out.csv").string() + " --plot " +
                                 (dir_ / "plot").string() + " --quiet");
    const std::vector<std::string> lines = split(readFile(dir_ / "out.csv"), '\n');
    if (lines.empty()) return;
    header_ = split(lines[0], ',');
    for (size_t i = 1; i < lines.size(); ++i) {
      if (lines[i].empty()) continue;
      const std::vector<std::string> cells = split(lines[i], ',');
      std::map<std::string, std::string> row;
      for (size_t k = 0; k < cells.size() && k < header_.size(); ++k) row[header_[k]] = cells[k];
      rows_[row["system"]] = row;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static double number(const std::string& system, const std::string& column) {
    return std::stod(rows_.at(system).at(column));
  }

  static inline fs::path dir_;
  static inline int status_ = -1;
  static inline std::vector<std::string> header_;
  static inline std::map<std::string, std::map<std::string, std::string>> rows_;
};

/// The shipped scans in the world frame, built here with the io library (not the harness).
std::vector<std::pair<Eigen::Vector3d, std::vector<Eigen::Vector3d>>> worldScans() {
  const auto poses = ndtom::io::readPoseFile(kData + "/poses.txt");
  std::vector<std::pair<Eigen::Vector3d, std::vector<Eigen::Vector3d>>> scans;
  for (int i = 0; i < kScans; ++i) {
    const auto cloud = ndtom::io::readPcd(kData + "/full" + std::to_string(i) + ".pcd");
    std::vector<Eigen::Vector3d> world;
    for (const auto& p : cloud.points)
      if (p.allFinite() && !p.isZero(0.0)) world.push_back(poses[i].pose * p);
    scans.emplace_back(poses[i].pose.translation(), world);
  }
  return scans;
}

}  // namespace

TEST_F(BenchSmoke, ExitsCleanlyWithOneRowPerSystem) {
  ASSERT_EQ(status_, 0) << readFile(dir_ / "err.txt");
  EXPECT_EQ(rows_.size(), 4u);
  for (const char* system : {"ndtom-point/t1", "ndtom-hitcell/t1", "octomap", "mrpt-grid3d"})
    EXPECT_EQ(rows_.count(system), 1u) << system;
  EXPECT_TRUE(fs::exists(dir_ / "plot_balm-realworld.png"));
}

TEST_F(BenchSmoke, NumbersArePositiveAndConsistent) {
  ASSERT_EQ(status_, 0);
  for (const auto& [system, row] : rows_) {
    SCOPED_TRACE(system);
    EXPECT_EQ(row.at("resolution_m"), "0.8");
    EXPECT_EQ(row.at("scans"), "2");
    EXPECT_GT(number(system, "median_ms"), 0);
    EXPECT_GE(number(system, "p95_ms"), number(system, "median_ms"));
    EXPECT_GT(number(system, "points_per_s"), 0);
    EXPECT_GT(number(system, "voxel_visits_per_s"), 0);
    EXPECT_GT(number(system, "memory_bytes"), 0);
    EXPECT_GT(number(system, "cells"), 0);
    EXPECT_NEAR(number(system, "bytes_per_cell"),
                number(system, "memory_bytes") / number(system, "cells"), 1e-3);
    // Points per second and the median are two views of the same timings.
    EXPECT_GT(number(system, "points_per_s") * number(system, "p95_ms") * 1e-3 * kScans,
              0.5 * number(system, "points"));
  }
  EXPECT_DOUBLE_EQ(number("octomap", "ratio_octomap"), 1.0);
  EXPECT_DOUBLE_EQ(number("mrpt-grid3d", "ratio_grid3d"), 1.0);
}

TEST_F(BenchSmoke, NdtomFiguresMatchAMapBuiltHere) {
  ASSERT_EQ(status_, 0);
  ndtom::MapOptions options;
  options.resolution = kResolution;
  options.scan.max_range = kMaxRange;
  ndtom::NdtMap map(options);
  size_t points = 0, visits = 0;
  for (const auto& [origin, world] : worldScans()) {
    points += world.size();
    visits += map.insertScan(world, origin).voxel_visits;
  }
  for (const auto& [system, row] : rows_) EXPECT_EQ(number(system, "points"), double(points));
  EXPECT_EQ(number("ndtom-point/t1", "voxel_visits"), double(visits));
  EXPECT_EQ(number("ndtom-point/t1", "cells"), double(map.numCells()));
  EXPECT_EQ(number("ndtom-point/t1", "memory_bytes"), double(map.memoryBytes()));
  // OctoMap's exact traversal in float visits (almost) the same cells as ours in double.
  EXPECT_NEAR(number("octomap", "voxel_visits"), double(visits), 0.02 * double(visits));
  // The grid's line walk takes one step per cell along the longest axis: fewer visits.
  EXPECT_LT(number("mrpt-grid3d", "voxel_visits"), double(visits));
}

TEST_F(BenchSmoke, SummaryHasTheTableAndTheTargets) {
  ASSERT_EQ(status_, 0);
  const std::string out = readFile(dir_ / "out.txt");
  for (const char* row :
       {"| balm-realworld | ndtom-point/t1 | 0.80 |",
        "| balm-realworld | ndtom-hitcell/t1 | 0.80 |", "| balm-realworld | octomap | 0.80 |",
        "| balm-realworld | mrpt-grid3d | 0.80 |"})
    EXPECT_NE(out.find(row), std::string::npos) << row;
  size_t verdicts = 0;
  for (const std::string& line : split(out, '\n'))
    if (line.find("[balm-realworld] PASS") != std::string::npos ||
        line.find("[balm-realworld] FAIL") != std::string::npos ||
        line.find("[balm-realworld] SKIP") != std::string::npos)
      ++verdicts;
  EXPECT_EQ(verdicts, 4u);
}

// Two threads: the map is compared with one thread's, and the speed-up is measured twice,
// in separate runs and side by side (runPaired), each in the CSV and the target's line.
TEST(BenchThreads, TwoThreadRunsReportIdentityAndBothSpeedups) {
  const fs::path dir =
      fs::temp_directory_path() / ("ndtom-bench-threads-" + std::to_string(getpid()));
  fs::create_directories(dir);
  ASSERT_EQ(runBench(dir, "--dataset " + kData +
                              " --scans 2 --resolutions 0.8 --systems ndtom-point --threads 1,2 "
                              "--quiet --csv " +
                              (dir / "out.csv").string()),
            0)
      << readFile(dir / "err.txt");
  const std::vector<std::string> lines = split(readFile(dir / "out.csv"), '\n');
  ASSERT_GE(lines.size(), 3u);
  const std::vector<std::string> header = split(lines[0], ',');
  std::map<std::string, std::map<std::string, std::string>> rows;
  for (size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> cells = split(lines[i], ',');
    for (size_t k = 0; k < cells.size() && k < header.size(); ++k)
      rows[cells[1]][header[k]] = cells[k];
  }
  ASSERT_EQ(rows.count("ndtom-point/t2"), 1u);
  const auto& t1 = rows["ndtom-point/t1"];
  const auto& t2 = rows["ndtom-point/t2"];
  EXPECT_EQ(t2.at("identical_to_t1"), "1");
  EXPECT_EQ(t1.at("speedup_vs_t1"), "");
  EXPECT_EQ(t1.at("speedup_vs_t1_side_by_side"), "");
  EXPECT_GT(std::stod(t2.at("speedup_vs_t1")), 0.0);
  EXPECT_GT(std::stod(t2.at("speedup_vs_t1_side_by_side")), 0.0);
  // The separate-runs figure is the ratio of the two rows' rates.
  EXPECT_NEAR(std::stod(t2.at("speedup_vs_t1")),
              std::stod(t2.at("points_per_s")) / std::stod(t1.at("points_per_s")),
              1e-3 * std::stod(t2.at("speedup_vs_t1")));
  const std::string out = readFile(dir / "out.txt");
  EXPECT_NE(out.find("side by side ("), std::string::npos) << out;

  // Amdahl from the one-thread run's stage profile: the same p and predictions in both rows,
  // each the formula of p, rising with the threads within [1, n]; CPU against one thread.
  for (const auto* row : {&t1, &t2}) {
    const double p = std::stod(row->at("parallel_fraction_t1"));
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
    EXPECT_EQ(row->at("parallel_fraction_t1"), t1.at("parallel_fraction_t1"));
    double last = 1;
    for (const int n : {2, 4, 8, 16}) {
      const double s = std::stod(row->at("predicted_s" + std::to_string(n)));
      EXPECT_NEAR(s, 1 / ((1 - p) + p / n), 1e-4 * s) << n;
      EXPECT_GE(s, last) << n;
      EXPECT_LE(s, n + 1e-9) << n;
      last = s;
    }
  }
  EXPECT_DOUBLE_EQ(std::stod(t1.at("cpu_ratio_vs_t1")), 1.0);
  EXPECT_GT(std::stod(t2.at("cpu_ratio_vs_t1")), 0.0);

  // The stages file beside the CSV: per run, the stages within the timed total, serial plus
  // parallel each stage's wall, busy time within threads x parallel wall; p from its totals.
  const std::vector<std::string> stage_lines = split(readFile(dir / "out.stages.csv"), '\n');
  ASSERT_GE(stage_lines.size(), 2u);
  const std::vector<std::string> stage_header = split(stage_lines[0], ',');
  std::map<std::string, double> stage_sums, totals, parallel_totals;
  std::map<std::string, std::vector<std::string>> stage_names;
  for (size_t i = 1; i < stage_lines.size(); ++i) {
    if (stage_lines[i].empty()) continue;
    const std::vector<std::string> cells = split(stage_lines[i], ',');
    std::map<std::string, std::string> c;
    for (size_t k = 0; k < cells.size() && k < stage_header.size(); ++k)
      c[stage_header[k]] = cells[k];
    const std::string system = c["system"];
    const double wall = std::stod(c["wall_s"]), serial = std::stod(c["serial_s"]);
    const double parallel = std::stod(c["parallel_wall_s"]), busy = std::stod(c["busy_s"]);
    SCOPED_TRACE(system + " " + c["stage"]);
    EXPECT_NEAR(serial + parallel, wall, 1e-6 + 1e-6 * wall);
    EXPECT_LE(busy, std::stod(c["threads"]) * parallel * (1 + 1e-6) + 1e-9);
    if (c["stage"] == "(all)") {
      totals[system] = wall;
      parallel_totals[system] = parallel;
    } else {
      stage_sums[system] += wall;
      stage_names[system].push_back(c["stage"]);
    }
  }
  for (const char* system :
       {"ndtom-point/t1", "ndtom-point/t2", "registration-p2d/t1", "registration-p2d/t2"}) {
    SCOPED_TRACE(system);
    ASSERT_EQ(totals.count(system), 1u);
    EXPECT_LE(stage_sums[system], totals[system] * (1 + 1e-6));
    EXPECT_GT(stage_sums[system], 0.5 * totals[system]);
  }
  EXPECT_EQ(
      stage_names["ndtom-point/t1"],
      (std::vector<std::string>{"setup", "classify", "sort", "group", "trace", "apply", "record"}));
  EXPECT_EQ(stage_names["registration-p2d/t1"],
            (std::vector<std::string>{"setup", "pyramid", "scan levels", "newton", "verdict"}));
  // The pyramid, built by the first call of each registration run, on its own row.
  for (const char* system : {"pyramid/t1", "pyramid/t2"}) {
    SCOPED_TRACE(system);
    ASSERT_EQ(totals.count(system), 1u);
    EXPECT_EQ(stage_names[system], std::vector<std::string>{"pyramid"});
    EXPECT_GT(parallel_totals[system], 0);  // its levels are built on the worker pool
    EXPECT_LE(parallel_totals[system], totals[system] * (1 + 1e-6));
  }
  EXPECT_NEAR(std::stod(t1.at("parallel_fraction_t1")),
              parallel_totals["ndtom-point/t1"] / totals["ndtom-point/t1"], 1e-5);
  // 16 threads busy for the predicted wall time: 16 / S(16).
  EXPECT_NEAR(std::stod(t1.at("predicted_cpu16_spinning")),
              16 / std::stod(t1.at("predicted_s16")), 1e-4);
  // Registration: two poses per thread count, the same for both.
  const size_t registration = out.find("| balm-realworld | registration-p2d/t2 | 0.80 | 2 |");
  ASSERT_NE(registration, std::string::npos) << out;
  const std::string line = out.substr(registration, out.find('\n', registration) - registration);
  EXPECT_EQ(line.substr(line.size() - 7), "| yes |") << line;
  EXPECT_NE(out.find("S(16) predicted"), std::string::npos) << out;
  EXPECT_NE(out.find("CPU(16) / 1 thread, workers spinning"), std::string::npos) << out;
  fs::remove_all(dir);
}

TEST(BenchBadInput, FailsWithOneLineMessage) {
  const fs::path dir = fs::temp_directory_path() / ("ndtom-bench-bad-" + std::to_string(getpid()));
  fs::create_directories(dir);
  for (const std::string& args : std::vector<std::string>{
           "", "--dataset /nonexistent/dataset", "--dataset " + kData + " --resolutions abc",
           "--dataset " + kData + " --systems bogus", "--dataset " + kData + " --scans 99",
           "--dataset " + kData + " --frobnicate 1",
           "--dataset " + kData + " --registration-scans -1"}) {
    SCOPED_TRACE(args);
    EXPECT_NE(runBench(dir, args), 0);
    const std::string err = readFile(dir / "err.txt");
    EXPECT_EQ(err.rfind("ndtom-bench: ", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  EXPECT_EQ(runBench(dir, "--help"), 0);
  EXPECT_NE(readFile(dir / "out.txt").find("--dataset"), std::string::npos);
  fs::remove_all(dir);
}
