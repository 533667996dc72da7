// Smoke test of ndtom-regbench on the shipped lidar scans (10 scans, 2 held out, 1 trial, two
// error levels; NDT-OM P2D and D2D on 1 and 2 threads, MRPT's ICP): the CSV files have their
// rows; each start is the reference pose moved by its level's error; each error and success
// flag follows from the final pose written and the reference (recomputed here); each level's
// counts and medians sum up its registrations; NDT-OM P2D registers both scans from
// 0.5 m / 5°. No timing assertions, no PCL, no shared datasets.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "ndtom_io/pose_file.h"
#include "support/program_run.h"

namespace fs = std::filesystem;
using ndtom::testing::Csv;
using ndtom::testing::CsvRow;
using ndtom::testing::ProgramRun;

namespace {

const std::string kExe = NDTOM_REGBENCH_EXE;
const std::string kData = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
const std::vector<std::string> kSystems = {"ndtom-p2d/t1", "ndtom-p2d/t2", "ndtom-d2d/t1",
                                           "ndtom-d2d/t2", "mrpt-icp"};
const std::vector<std::pair<double, double>> kLevels = {{0.5, 5}, {2, 20}};  // m, degrees
const std::vector<int> kHeldOut = {3, 6};

double field(const CsvRow& row, const std::string& column) {
  return std::stod(row.at(column));
}

Eigen::Isometry3d poseOf(const CsvRow& row, const std::string& prefix) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << field(row, prefix + "x"), field(row, prefix + "y"),
      field(row, prefix + "z");
  pose.linear() = Eigen::Quaterniond(field(row, prefix + "qw"), field(row, prefix + "qx"),
                                     field(row, prefix + "qy"), field(row, prefix + "qz"))
                      .normalized()
                      .toRotationMatrix();
  return pose;
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool sameLevel(const CsvRow& a, const CsvRow& b) {
  return a.at("system") == b.at("system") && a.at("translation_m") == b.at("translation_m");
}

class RegbenchSmoke : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("ndtom-regbench-smoke-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    run_ = ndtom::testing::runProgram(
        kExe,
        "--dataset '" + kData + "' --held-out 3,6 --trials 1 --errors 0.5/5,2/20 --systems " +
            "ndtom-p2d,ndtom-d2d,mrpt-icp --threads 1,2 --csv '" + (dir_ / "levels.csv").string() +
            "' --trials-csv '" + (dir_ / "trials.csv").string() + "' --plot '" +
            (dir_ / "success.png").string() + "' --quiet",
        dir_);
    levels_ = ndtom::testing::readCsv(dir_ / "levels.csv");
    trials_ = ndtom::testing::readCsv(dir_ / "trials.csv");
    for (const auto& p : ndtom::io::readPoseFile(kData + "/poses.txt")) poses_.push_back(p.pose);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static inline fs::path dir_;
  static inline ProgramRun run_;
  static inline Csv levels_, trials_;
  static inline std::vector<Eigen::Isometry3d> poses_;
};

}  // namespace

TEST_F(RegbenchSmoke, WritesOneRowPerSystemThreadsAndLevel) {
  ASSERT_EQ(run_.exit_code, 0) << run_.stderr_text;
  ASSERT_EQ(levels_.rows.size(), kSystems.size() * kLevels.size());
  for (const std::string& system : kSystems)
    for (const auto& [meters, degrees] : kLevels) {
      SCOPED_TRACE(system + " " + std::to_string(meters));
      const auto matches =
          std::count_if(levels_.rows.begin(), levels_.rows.end(), [&](const CsvRow& r) {
            return r.at("system") == system && field(r, "translation_m") == meters &&
                   field(r, "rotation_deg") == degrees;
          });
      EXPECT_EQ(matches, 1);
    }
  EXPECT_EQ(trials_.rows.size(), kSystems.size() * kLevels.size() * kHeldOut.size());
  EXPECT_EQ(ndtom::testing::readFile(dir_ / "success.png").substr(1, 3), "PNG");
}

TEST_F(RegbenchSmoke, StartsAreTheLevelErrorsAndTheSameForEverySystem) {
  ASSERT_EQ(run_.exit_code, 0);
  std::set<std::string> starts;  // distinct starts, as written
  for (const CsvRow& r : trials_.rows) {
    SCOPED_TRACE(r.at("system") + " scan " + r.at("scan") + " at " + r.at("translation_m"));
    const Eigen::Isometry3d& truth = poses_.at(size_t(std::stoi(r.at("scan"))));
    const Eigen::Isometry3d start = poseOf(r, "start_");
    const Eigen::Vector3d offset = start.translation() - truth.translation();
    EXPECT_NEAR(offset.norm(), field(r, "translation_m"), 1e-6);
    EXPECT_NEAR(offset.z(), 0, 1e-6);  // horizontal
    EXPECT_NEAR(angleDeg(start.linear(), truth.linear()), field(r, "rotation_deg"), 1e-5);
    // Turned about the world's vertical axis.
    const Eigen::AngleAxisd turn(start.linear() * truth.linear().transpose());
    EXPECT_NEAR(std::abs(turn.axis().z()), 1, 1e-6);
    std::string key = r.at("scan") + "," + r.at("translation_m") + "," + r.at("trial");
    for (const char* c :
         {"start_x", "start_y", "start_z", "start_qw", "start_qx", "start_qy", "start_qz"})
      key += "," + r.at(c);
    starts.insert(key);
  }
  EXPECT_EQ(starts.size(), kLevels.size() * kHeldOut.size());  // one start, whatever the system
}

TEST_F(RegbenchSmoke, ErrorsAndSuccessFlagsFollowFromTheFinalPoses) {
  ASSERT_EQ(run_.exit_code, 0);
  for (const CsvRow& r : trials_.rows) {
    SCOPED_TRACE(r.at("system") + " scan " + r.at("scan") + " at " + r.at("translation_m"));
    const Eigen::Isometry3d& truth = poses_.at(size_t(std::stoi(r.at("scan"))));
    const Eigen::Isometry3d pose = poseOf(r, "");
    const double meters = (pose.translation() - truth.translation()).norm();
    const double degrees = angleDeg(pose.linear(), truth.linear());
    EXPECT_NEAR(field(r, "error_m"), meters, 1e-6);
    EXPECT_NEAR(field(r, "error_deg"), degrees, 1e-4);
    EXPECT_EQ(r.at("success"), meters <= 0.10 && degrees <= 1.0 ? "1" : "0");
    EXPECT_GT(field(r, "ms"), 0);
  }
}

TEST_F(RegbenchSmoke, EachLevelRowSumsUpItsRegistrations) {
  ASSERT_EQ(run_.exit_code, 0);
  for (const CsvRow& level : levels_.rows) {
    SCOPED_TRACE(level.at("system") + " at " + level.at("translation_m"));
    int trials = 0, successes = 0, converged = 0, wrong = 0, missed = 0;
    std::vector<double> meters, degrees;
    for (const CsvRow& t : trials_.rows) {
      if (!sameLevel(level, t)) continue;
      ++trials;
      const bool success = t.at("success") == "1";
      if (success) {
        ++successes;
        meters.push_back(field(t, "error_m"));
        degrees.push_back(field(t, "error_deg"));
      }
      converged += t.at("converged") == "1";
      wrong += t.at("converged") == "1" && !success;
      missed += t.at("converged") == "0" && success;
    }
    EXPECT_EQ(field(level, "trials"), trials);
    EXPECT_EQ(field(level, "successes"), successes);
    EXPECT_NEAR(field(level, "success_rate"), double(successes) / trials, 1e-9);
    if (successes > 0) {
      EXPECT_NEAR(field(level, "median_error_m"), median(meters), 1e-9);
      EXPECT_NEAR(field(level, "median_error_deg"), median(degrees), 1e-7);
    }
    if (level.at("system").rfind("ndtom-", 0) == 0) {
      EXPECT_EQ(field(level, "converged"), converged);
      EXPECT_EQ(field(level, "wrong_converged"), wrong);
      EXPECT_EQ(field(level, "false_failures"), missed);
      EXPECT_EQ(level.at("level_resolutions_m"), "3.2;1.6;0.8;0.4;0.2");
    } else {  // MRPT's ICP gives no verdict
      EXPECT_EQ(level.at("converged"), "");
      EXPECT_EQ(level.at("level_resolutions_m"), "");
    }
  }
}

TEST_F(RegbenchSmoke, NdtomP2DRegistersBothScansFromHalfAMetre) {
  ASSERT_EQ(run_.exit_code, 0);
  for (const CsvRow& r : levels_.rows)
    if (r.at("system").rfind("ndtom-p2d/", 0) == 0 && r.at("translation_m") == "0.5") {
      EXPECT_EQ(field(r, "successes"), kHeldOut.size()) << r.at("system");
      EXPECT_EQ(field(r, "wrong_converged"), 0) << r.at("system");
      EXPECT_EQ(field(r, "false_failures"), 0) << r.at("system");
    }
}

TEST_F(RegbenchSmoke, TwoThreadsGiveTheSamePosesAsOne) {
  ASSERT_EQ(run_.exit_code, 0);
  size_t compared = 0;
  for (const CsvRow& two : trials_.rows) {
    const std::string& system = two.at("system");
    if (system.size() < 3 || system.substr(system.size() - 3) != "/t2") continue;
    for (const CsvRow& one : trials_.rows)
      if (one.at("system") == system.substr(0, system.size() - 1) + "1" &&
          one.at("scan") == two.at("scan") && one.at("translation_m") == two.at("translation_m")) {
        for (const char* c : {"x", "y", "z", "qw", "qx", "qy", "qz"})
          EXPECT_EQ(one.at(c), two.at(c)) << system << " scan " << two.at("scan") << " " << c;
        ++compared;
      }
  }
  EXPECT_EQ(compared, 2 * kLevels.size() * kHeldOut.size());
}

TEST_F(RegbenchSmoke, SummaryHasTheTablesAndTheTargets) {
  ASSERT_EQ(run_.exit_code, 0);
  const std::string& out = run_.stdout_text;
  for (const char* text : {"CPU: ", "Build: ", "Peers: MRPT 2.5.8", "### Systems", "### Successes",
                           "| ndtom-p2d/t1 | 0.5 m / 5° | ", "| mrpt-icp | 2 m / 20° | ",
                           "### NDT-OM: mean time and Newton steps per pyramid level"})
    EXPECT_NE(out.find(text), std::string::npos) << text;
  for (const char* system : {"ndtom-p2d/t1: ", "ndtom-d2d/t1: "}) {
    size_t verdicts = 0;
    for (const char* verdict : {"  PASS ", "  FAIL ", "  SKIP "})
      for (size_t at = out.find(verdict + std::string(system)); at != std::string::npos;
           at = out.find(verdict + std::string(system), at + 1))
        ++verdicts;
    EXPECT_EQ(verdicts, 5u) << system;  // two success targets, accuracy, verdicts, time
  }
  EXPECT_TRUE(run_.stderr_text.empty()) << run_.stderr_text;  // --quiet
}

TEST(RegbenchBadInput, FailsWithOneLineMessage) {
  const fs::path dir =
      fs::temp_directory_path() / ("ndtom-regbench-bad-" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string data = "--dataset '" + kData + "'";
  for (const auto& [args, status] :
       std::vector<std::pair<std::string, int>>{{"", 2},
                                                {"--dataset /nonexistent/folder", 1},
                                                {data + " --held-out 3,99", 1},
                                                {data + " --held-out 3,3", 2},
                                                {data + " --trials 0", 2},
                                                {data + " --errors 1", 2},
                                                {data + " --errors 1/x", 2},
                                                {data + " --systems bogus", 2},
                                                {data + " --threads 0", 2},
                                                {data + " --csv /nonexistent/folder/out.csv", 1},
                                                {data + " --frobnicate 1", 2}}) {
    SCOPED_TRACE(args);
    const ProgramRun run = ndtom::testing::runProgram(kExe, args + " --quiet", dir);
    EXPECT_EQ(run.exit_code, status);
    EXPECT_EQ(run.stderr_text.rfind("ndtom-regbench: ", 0), 0u) << run.stderr_text;
    EXPECT_EQ(std::count(run.stderr_text.begin(), run.stderr_text.end(), '\n'), 1)
        << run.stderr_text;
  }
  const ProgramRun help = ndtom::testing::runProgram(kExe, "--help", dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.stdout_text.find("--held-out"), std::string::npos);
  fs::remove_all(dir);
}
