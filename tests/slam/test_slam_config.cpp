// ndtom-slam --config: CMetricMapBuilderNDT's .ini sections (share/mrpt/ndtom-slam.ini), with
// the flags given winning over the file; bad files fail naming the section and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "mapper/mapper_run.h"
#include "slam/loop_checks.h"
#include "ndtom_io/pose_file.h"
#include "mrpt/sena_log.h"

using namespace mapper_test;

namespace {

const std::string kSlam = NDTOM_SLAM_EXE;

const char* kConfig = R"ini(
[NDTSLAM]
recovery_radius      = 3
target_radius        = 40
min_matched_fraction = 0.3
retry_without_finest = false
free_space_overrule  = 0.05

[NDTSLAM_ndtOccupancyMap_00_insertOpts]
resolution = 0.25
max_range  = 30

[other]
recovery_radius = 1.5
)ini";

std::string writeConfig(const TempDir& dir, const std::string& text) {
  const std::string path = (dir / "slam.ini").string();
  std::ofstream(path) << text;
  return path;
}

// ndtom-slam on the shipped scans with `args`; the summary's text ("" if it failed).
std::string summaryOf(const TempDir& dir, const std::string& args, ProgramRun* run = nullptr) {
  const std::string prefix = (dir / "run").string();
  fs::remove(prefix + ".summary.json");
  const ProgramRun r = runExecutable(
      kSlam, quoted(kLidar) + " -o " + quoted(prefix) + " --no-pictures -q " + args, dir);
  if (run) *run = r;
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  return readText(prefix + ".summary.json");
}

}  // namespace

TEST(SlamConfig, TheFileSetsTheOptionsAndFlagsWinOverIt) {
  TempDir dir;
  const std::string ini = quoted(writeConfig(dir, kConfig));
  const std::string from_file = summaryOf(dir, "--config " + ini);
  EXPECT_EQ(jsonNumber(from_file, "recovery_radius"), 3);
  EXPECT_EQ(jsonNumber(from_file, "target_radius"), 40);
  EXPECT_EQ(jsonNumber(from_file, "min_matched_fraction"), 0.3);
  EXPECT_EQ(jsonNumber(from_file, "resolution"), 0.25);
  EXPECT_EQ(jsonNumber(from_file, "lost"), 0);
  EXPECT_NE(from_file.find("\"retry_without_finest\": false"), std::string::npos);
  EXPECT_EQ(jsonNumber(from_file, "free_space_overrule"), 0.05);

  // Flags before or after --config, the online mapper's and the map's, win.
  const std::string flags =
      summaryOf(dir, "--min-matched-fraction 0.35 --config=" + ini +
                         " --resolution 0.2 --recovery-radius 2.5 --retry-without-finest on"
                         " --free-space-overrule 0");
  EXPECT_EQ(jsonNumber(flags, "min_matched_fraction"), 0.35);
  EXPECT_EQ(jsonNumber(flags, "resolution"), 0.2);
  EXPECT_EQ(jsonNumber(flags, "recovery_radius"), 2.5);
  EXPECT_NE(flags.find("\"retry_without_finest\": true"), std::string::npos);
  EXPECT_EQ(jsonNumber(flags, "free_space_overrule"), 0);
  EXPECT_EQ(jsonNumber(flags, "target_radius"), 40) << "the file's, where no flag is given";

  // Another section: its keys, the rest at the defaults (no map section for it).
  const std::string other = summaryOf(dir, "--config " + ini + " --section other");
  EXPECT_EQ(jsonNumber(other, "recovery_radius"), 1.5);
  EXPECT_EQ(jsonNumber(other, "target_radius"), 50);
  EXPECT_EQ(jsonNumber(other, "resolution"), 0.2);
}

TEST(SlamConfig, BadFilesAreRefusedNamingTheSectionAndTheKey) {
  TempDir dir;
  struct Case {
    std::string text, args, expected[2];
  };
  const std::vector<Case> cases = {
      {"[NDTSLAM]\ntarget_radius = 40m\n", "", {"[NDTSLAM]", "target_radius"}},
      {"[NDTSLAM]\nrecovery_yaw_deg = 400\n", "", {"[NDTSLAM]", "recovery_yaw_deg"}},
      {"[NDTSLAM]\nrecovery_radious = 3\n", "", {"[NDTSLAM]", "unknown key 'recovery_radious'"}},
      {"[NDTSLAM_ndtOccupancyMap_00_insertOpts]\nresolution = -1\n",
       "",
       {"NDTSLAM_ndtOccupancyMap_00_insertOpts", "resolution"}},
      {"[NDTSLAM]\nplanar = true\n", "--section missing", {"no section [missing]", "--section"}},
      {"[NDTSLAM]\n", "--section", {"--section", "missing value"}},
  };
  for (const Case& c : cases) {
    const std::string ini = quoted(writeConfig(dir, c.text));
    const ProgramRun run = runExecutable(
        kSlam,
        quoted(kLidar) + " -o " + quoted((dir / "x").string()) + " --config " + ini + " " + c.args,
        dir);
    EXPECT_EQ(run.exit_code, 2) << c.text << run.err;
    for (const std::string& part : c.expected)
      EXPECT_NE(run.err.find(part), std::string::npos) << c.text << " -> " << run.err;
    EXPECT_TRUE(outputsOf(dir, "x").empty());
  }
  const ProgramRun none = runExecutable(kSlam,
                                        quoted(kLidar) + " -o " + quoted((dir / "x").string()) +
                                            " --config " + quoted((dir / "absent.ini").string()),
                                        dir);
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("absent.ini"), std::string::npos) << none.err;
}

TEST(SlamConfig, TheShippedConfigTracksMrptsSenaLoop) {
  if (!fs::exists(kSenaRawlog)) GTEST_SKIP() << "no SENA log (Debian's mrpt-common)";
  TempDir dir;
  const std::string prefix = (dir / "sena").string();
  const ProgramRun run =
      runExecutable(kSlam,
                    quoted(kSenaRawlog) + " -o " + quoted(prefix) + " --no-pictures -q --config " +
                        quoted(std::string(NDTOM_SOURCE_DIR) + "/share/mrpt/ndtom-slam.ini"),
                    dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  // Every scan of the log; MRPT's action/frame reader (icp-slam's) skips the first, which
  // comes before any action.
  EXPECT_EQ(jsonNumber(json, "scans"), 225);
  EXPECT_EQ(jsonNumber(json, "lost"), 0);
  EXPECT_EQ(jsonNumber(json, "resolution"), 0.2);
}

namespace {

// Mean distance to MRPT's reference poses of the scans it has (matched by time stamp).
double meanReferenceError(const std::vector<ndtom::io::StampedPose>& poses,
                          const std::map<long, mrpt::poses::CPose3D>& reference) {
  double sum = 0;
  size_t compared = 0;
  for (const ndtom::io::StampedPose& p : poses) {
    const auto it = reference.find(std::lround(p.time * 1e3));  // keyed by time stamp in ms
    if (it == reference.end()) continue;
    const Eigen::Vector3d& t = p.pose.translation();
    sum += std::hypot(t.x() - it->second.x(), t.y() - it->second.y());
    ++compared;
  }
  EXPECT_GT(compared, 50u);
  return sum / double(compared);
}

}  // namespace

// With --loop-closure on, the SENA loop closes: between scans far apart in the log that the
// odometry-only run puts within a submap of each other, and the optimized trajectory is no
// further from MRPT's reference poses than odometry alone.
TEST(SlamConfig, TheShippedConfigClosesMrptsSenaLoop) {
  if (!fs::exists(kSenaRawlog)) GTEST_SKIP() << "no SENA log (Debian's mrpt-common)";
  const auto reference = ndtom::testing::senaReferencePoses();
  ASSERT_GT(reference.size(), 50u);
  TempDir dir;
  const auto slam = [&](const std::string& loop_closure) {
    const std::string prefix = (dir / loop_closure).string();
    const ProgramRun run = runExecutable(
        kSlam, quoted(kSenaRawlog) + " -o " + quoted(prefix) + " --no-pictures -q --config " +
                   quoted(std::string(NDTOM_SOURCE_DIR) + "/share/mrpt/ndtom-slam.ini") +
                   " --loop-closure " + loop_closure,
        dir);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return prefix;
  };
  const std::string on = slam("on"), off = slam("off");
  const std::string json = readText(on + ".summary.json");
  EXPECT_GE(jsonNumber(json, "accepted", "loop_closure"), 1);
  // Their trajectories, one line a scan.
  const auto odometry = ndtom::io::readPoseFile(off + ".tum", ndtom::io::PoseFormat::Tum);
  const auto optimized = ndtom::io::readPoseFile(on + ".tum", ndtom::io::PoseFormat::Tum);
  ASSERT_EQ(odometry.size(), 225u);
  ASSERT_EQ(optimized.size(), 225u);
  size_t loops = 0;
  for (const slam_test::CheckedLoop& loop : slam_test::checkedLoops(json)) {
    if (!loop.accepted) continue;
    const size_t older = loop.older_scan, newer = loop.newer_scan;
    ASSERT_LT(newer, odometry.size());
    SCOPED_TRACE(testing::Message() << "loop between scans " << older << " and " << newer);
    EXPECT_GE(newer - older, 100u);  // round the loop, not the last few metres
    // The scan is registered to the older keyframe's submap, which reaches a keyframe's
    // length (10 m by default) past that keyframe's first scan, `older`.
    const Eigen::Vector3d apart =
        odometry[newer].pose.translation() - odometry[older].pose.translation();
    EXPECT_LT(std::hypot(apart.x(), apart.y()), 10.0);
    ++loops;
  }
  EXPECT_GE(loops, 1u);
  const double with_loops = meanReferenceError(optimized, reference);
  const double without = meanReferenceError(odometry, reference);
  std::printf("reference error: %.3f m with loop closure, %.3f m without\n", with_loops, without);
  EXPECT_LT(with_loops, without + 0.02);
  EXPECT_LT(with_loops, 0.2);
}
