// ndtom-slam's loop closure end to end on a small ndtom-worldgen drive that comes back through
// the street it started in (one block round, 340 m, range noise 0.08 m so that odometry drifts):
// every loop edge against the drive's true poses, the live map corrected during the run (the
// pose known at the end of the drive is the corrected one, not odometry's), the graph read by
// MRPT, and the map rebuilt from PREFIX.tum byte for byte.
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>

#include "mapper/mapper_run.h"
#include "slam/loop_checks.h"
#include "ndtom_io/pose_file.h"

using namespace mapper_test;

namespace {

const std::string kSlam = NDTOM_SLAM_EXE;
const std::string kWorldgen = NDTOM_WORLDGEN_EXE;
const std::string kMapOptions = " --resolution 0.2 --max-range 30 --no-pictures -q ";

// The "keyframe_first_scans" array of the summary.
std::vector<size_t> keyframeFirstScans(const std::string& json) {
  std::vector<size_t> out;
  size_t at = json.find("\"keyframe_first_scans\":");
  if (at == std::string::npos) return out;
  at = json.find('[', at);
  const size_t end = json.find(']', at);
  for (const char* p = json.c_str() + at + 1; p < json.c_str() + end;) {
    char* next = nullptr;
    const double v = std::strtod(p, &next);
    if (next == p) {
      ++p;
      continue;
    }
    out.push_back(size_t(v));
    p = next;
  }
  return out;
}

}  // namespace

TEST(SlamLoopClosure, ClosesTheBlockAndCorrectsTheLiveMapAndItsTrajectoryRebuildsTheMap) {
  TempDir dir;
  const fs::path city = dir / "city";
  const ProgramRun world = runExecutable(
      kWorldgen, quoted(city.string()) + " --km 0.34 --step 1 --blocks 1 --noise 0.08 -q", dir);
  ASSERT_EQ(world.exit_code, 0) << world.err;
  const std::string prefix = (dir / "run").string();
  const ProgramRun run = runExecutable(
      kSlam,
      quoted(city.string()) + " -o " + quoted(prefix) + kMapOptions + "--loop-closure on " +
          "--reference " + quoted((city / "poses.txt").string()),
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_GE(jsonNumber(json, "accepted", "loop_closure"), 1);
  EXPECT_GE(jsonNumber(json, "live_corrections", "loop_closure"), 1);

  // The optimized trajectory beats odometry's, and the pose the run knew at the end of the
  // drive was corrected by the loops closed on the way (odometry alone ends ~0.4 m off; how
  // much of that the live map keeps depends on when the last loop closed before the end:
  // 0.09 m after one correction, 0.29 m after two later ones; without any, as odometry).
  const double with_loops = jsonNumber(json, "ate_rmse_m", "reference");
  const double odometry = jsonNumber(json, "ate_rmse_m", "odometry_reference");
  EXPECT_LT(with_loops, odometry) << "ATE " << with_loops << " m, odometry's " << odometry;
  const double live_final = jsonNumber(json, "final_error_m", "live_reference");
  const double odometry_final = jsonNumber(json, "final_error_m", "odometry_reference");
  EXPECT_GT(odometry_final, 0.2) << "odometry barely drifted: the test shows nothing";
  EXPECT_LT(live_final, 0.8 * odometry_final)
      << "live " << live_final << " m, odometry " << odometry_final << " m at the end";

  // MRPT reads the graph: a node per keyframe, the loops among its edges, and every loop
  // edge is the true motion between its keyframes' first scans (the drive's own poses).
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  graph.loadFromTextFile(prefix + ".graph");
  EXPECT_EQ(double(graph.nodes.size()), jsonNumber(json, "keyframes", "loop_closure"));
  EXPECT_EQ(double(graph.edgeCount()),
            double(graph.nodes.size()) - 1 + jsonNumber(json, "accepted", "loop_closure"));
  const std::vector<size_t> first = keyframeFirstScans(json);
  ASSERT_EQ(first.size(), graph.nodes.size());
  std::vector<Eigen::Isometry3d> truth;
  for (const auto& p : ndtom::io::readPoseFile((city / "poses.txt").string()))
    truth.push_back(p.pose);
  size_t loops = 0;
  for (const auto& [ids, edge] : graph.edges) {
    if (ids.second == ids.first + 1) continue;
    ++loops;
    const Eigen::Vector3d measured(edge.mean.x(), edge.mean.y(), edge.mean.z());
    const Eigen::Vector3d expected =
        (truth.at(first.at(ids.first)).inverse() * truth.at(first.at(ids.second))).translation();
    EXPECT_LT((measured - expected).norm(), 0.1) << "loop " << ids.first << " - " << ids.second;
    EXPECT_GT(first.at(ids.second) - first.at(ids.first), 200u) << "round the block";
  }
  EXPECT_GE(loops, 1u);

  // ndtom-map with the optimized trajectory: the same map, byte for byte.
  ASSERT_EQ(jsonNumber(json, "lost"), 0);  // ndtom-map inserts every scan; a lost one is not
  const std::string rebuilt = (dir / "rebuilt").string();
  const ProgramRun map = runMapper(quoted(city.string()) + " --poses " + quoted(prefix + ".tum") +
                                       " -o " + quoted(rebuilt) + kMapOptions,
                                   dir);
  ASSERT_EQ(map.exit_code, 0) << map.err;
  EXPECT_TRUE(sameBytes(readText(prefix + ".ndtom"), readText(rebuilt + ".ndtom")));
}

// Every block the same (ndtom-worldgen --identical-blocks): a street looks like the next one.
// A loop accepted between scans whose true positions are far apart is a false closure.
TEST(SlamLoopClosure, LookAlikeStreetsAreNeverClosedTogether) {
  TempDir dir;
  const fs::path city = dir / "city";
  const ProgramRun world = runExecutable(
      kWorldgen, quoted(city.string()) + " --km 0.34 --step 1 --blocks 2 --identical-blocks -q",
      dir);
  ASSERT_EQ(world.exit_code, 0) << world.err;
  const std::string prefix = (dir / "run").string();
  const ProgramRun run = runExecutable(
      kSlam, quoted(city.string()) + " -o " + quoted(prefix) + kMapOptions + "--loop-closure on",
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<Eigen::Isometry3d> truth;
  for (const auto& p : ndtom::io::readPoseFile((city / "poses.txt").string()))
    truth.push_back(p.pose);
  const std::string json = readText(prefix + ".summary.json");
  const std::vector<slam_test::CheckedLoop> loops = slam_test::checkedLoops(json);
  size_t accepted = 0;
  for (const slam_test::CheckedLoop& loop : loops) {
    if (!loop.accepted) continue;
    ++accepted;
    const size_t older = loop.older_scan, newer = loop.newer_scan;
    const double apart = (truth.at(older).translation() - truth.at(newer).translation()).norm();
    // A keyframe's submap reaches its length (10 m) past its first scan.
    EXPECT_LT(apart, 15.0) << "scans " << older << " and " << newer;
  }
  ASSERT_FALSE(loops.empty()) << "no loop candidate: the test shows nothing";
  EXPECT_GE(accepted, 1u);  // the true loop is still closed
}
