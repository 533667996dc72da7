// ndtom-slam as a user runs it, on the shipped BALM scans (their poses.txt not read).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "mapper/mapper_run.h"
#include "ndtom_io/pcd_reader.h"

using namespace mapper_test;

namespace {

const std::string kSlam = NDTOM_SLAM_EXE;
const std::string kMapOptions = " --resolution 0.2 --max-range 30 ";

size_t lineCount(const std::string& text) {
  size_t n = 0;
  for (const char c : text) n += c == '\n';
  return n;
}

}  // namespace

TEST(SlamEndToEnd, MapsTheShippedScansAndItsTrajectoryRebuildsTheSameMap) {
  TempDir dir;
  const std::string prefix = (dir / "run").string();
  const ProgramRun run = runExecutable(
      kSlam,
      quoted(kLidar) + " -o " + quoted(prefix) + kMapOptions + "--reference " +
          quoted(kLidar + "/poses.txt"),
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* suffix : {".ndtom", ".ndtommap", ".3Dscene", ".top.png", ".3d.png", ".tum",
                             ".summary.json"})
    EXPECT_TRUE(fs::exists(prefix + suffix)) << suffix;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "scans"), 10);
  EXPECT_EQ(jsonNumber(json, "lost"), 0);
  EXPECT_LT(jsonNumber(json, "ate_rmse_m"), 0.03);
  EXPECT_EQ(lineCount(readText(prefix + ".tum")), 10u);
  EXPECT_NE(run.out.find("10 scans"), std::string::npos) << run.out;
  EXPECT_NE(run.err.find("mapping"), std::string::npos);  // progress

  // ndtom-map with the trajectory: the same map, byte for byte.
  const std::string rebuilt = (dir / "rebuilt").string();
  const ProgramRun map = runMapper(quoted(kLidar) + " --poses " + quoted(prefix + ".tum") +
                                       " -o " + quoted(rebuilt) + kMapOptions + "--no-pictures -q",
                                   dir);
  ASSERT_EQ(map.exit_code, 0) << map.err;
  EXPECT_TRUE(sameBytes(readText(prefix + ".ndtom"), readText(rebuilt + ".ndtom")));
  // ... and not the map of the shipped poses (the check can fail).
  const std::string shipped = (dir / "shipped").string();
  ASSERT_EQ(runMapper(quoted(kLidar) + " -o " + quoted(shipped) + kMapOptions + "--no-pictures -q",
                      dir)
                .exit_code,
            0);
  EXPECT_FALSE(sameBytes(readText(prefix + ".ndtom"), readText(shipped + ".ndtom")));
}

TEST(SlamEndToEnd, OptionsThatGivePosesAreRefused) {
  TempDir dir;
  for (const std::string& option : {"--poses " + quoted(kLidar + "/poses.txt"), std::string("--passes 2"),
                                   std::string("--resident-budget 10")}) {
    const ProgramRun run = runExecutable(
        kSlam, quoted(kLidar) + " -o " + quoted((dir / "x").string()) + " " + option, dir);
    EXPECT_EQ(run.exit_code, 2) << option;
    EXPECT_NE(run.err.find("finds the poses itself"), std::string::npos) << run.err;
    EXPECT_TRUE(outputsOf(dir, "x").empty());
  }
  const ProgramRun bad = runExecutable(
      kSlam, quoted(kLidar) + " -o " + quoted((dir / "x").string()) + " --recovery-yaw 400", dir);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("recovery_yaw_deg"), std::string::npos) << bad.err;
}

TEST(SlamEndToEnd, AFolderWithoutScansIsAClearError) {
  TempDir dir;
  fs::create_directories(dir / "empty");
  const ProgramRun run = runExecutable(
      kSlam, quoted((dir / "empty").string()) + " -o " + quoted((dir / "x").string()), dir);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("nor .pcd files"), std::string::npos) << run.err;
}

// A folder of the shipped scans 0-5 with scan 3 replaced by an empty one, and its time stamps.
fs::path scansWithAnEmptyOne(const TempDir& dir, const std::vector<double>& times) {
  const fs::path folder = dir / "scans";
  fs::create_directories(folder);
  for (int i = 0; i < 6; ++i) {
    const std::string name = "full" + std::to_string(i) + ".pcd";
    if (i == 3)
      ndtom::io::writePcdBinary((folder / name).string(), {});
    else
      fs::copy_file(kLidar + "/" + name, folder / name);
  }
  std::ofstream out(folder / "times.txt");
  for (const double t : times) out << std::setprecision(17) << t << "\n";
  return folder;
}

// An empty scan is lost and counted, never inserted; the run goes on and the next scans are
// placed. Time going backwards stops the run, naming the scan.
TEST(SlamEndToEnd, AnEmptyScanIsLostAndTimeGoingBackwardsIsAnError) {
  TempDir dir;
  const fs::path folder = scansWithAnEmptyOne(dir, {0, 0.5, 1, 1.5, 2, 2.5});
  const std::string prefix = (dir / "run").string();
  const ProgramRun run =
      runExecutable(kSlam, quoted(folder.string()) + " -o " + quoted(prefix) + kMapOptions + "-q", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "scans"), 6);
  EXPECT_EQ(jsonNumber(json, "lost"), 1);
  EXPECT_NE(json.find("no finite point"), std::string::npos);
  EXPECT_EQ(lineCount(readText(prefix + ".tum")), 6u);

  TempDir dir2;
  const fs::path backwards = scansWithAnEmptyOne(dir2, {0, 0.5, 1, 0.7, 2, 2.5});
  const ProgramRun bad = runExecutable(
      kSlam, quoted(backwards.string()) + " -o " + quoted((dir2 / "x").string()) + kMapOptions, dir2);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("full3.pcd"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("time goes backwards"), std::string::npos) << bad.err;
  EXPECT_TRUE(outputsOf(dir2, "x").empty());
}

// A rawlog without range data (only odometry) has nothing to map: a clear error.
TEST(SlamEndToEnd, ARawlogWithoutRangeDataIsAClearError) {
  TempDir dir;
  const std::string rawlog = std::string(MRPT_DATASETS) + "/RO-SLAM_demo.rawlog";
  if (!fs::exists(rawlog)) GTEST_SKIP() << rawlog << " absent";
  const ProgramRun run =
      runExecutable(kSlam, quoted(rawlog) + " -o " + quoted((dir / "x").string()), dir);
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("no scans"), std::string::npos) << run.err;
}

// Loop closure must not make the lidar sequence worse: its 60 scans (74 m of campus, no loop)
// with --loop-closure on run on a window of keyframes and still end within 3 cm (ATE) of the
// shipped poses, as odometry on the whole map does. The sequence is in ../shared only.
TEST(SlamEndToEnd, LoopClosureKeepsTheWholeLidarSequenceWithin3Centimetres) {
  const std::string sequence = std::string(NDTOM_SHARED_DATASETS) + "/balm-realworld";
  if (!fs::exists(sequence + "/full59.pcd")) GTEST_SKIP() << "no " << sequence;
  TempDir dir;
  const std::string prefix = (dir / "run").string();
  const ProgramRun run = runExecutable(
      kSlam,
      quoted(sequence) + " -o " + quoted(prefix) + kMapOptions +
          "--no-pictures -q --loop-closure on --reference " + quoted(sequence + "/poses.txt"),
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "scans"), 60);
  EXPECT_EQ(jsonNumber(json, "lost"), 0);
  EXPECT_GE(jsonNumber(json, "keyframes", "loop_closure"), 4) << "the window was used";
  EXPECT_LT(jsonNumber(json, "ate_rmse_m", "reference"), 0.03);
}
