// Global localization without an initial pose: the ground of a scan against a known plane,
// a held-out real lidar scan found in a map of the others (shipped BALM subset), a scan of
// another place reported "not found", and the local search around a wrong prediction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/synthetic_room.h"
#include "ndtom/localization/global_localization.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using namespace ndtom;
namespace room = ndtom::testing;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

const double kDeg = M_PI / 180;
const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

double rotationErrorDeg(const Isometry3d& a, const Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

struct Balm {
  std::vector<Isometry3d> poses;
  std::vector<std::vector<Vector3d>> scans;  // sensor frame

  Balm() {
    for (const auto& p : io::readPoseFile(kBalm + "/poses.txt")) poses.push_back(p.pose);
    for (int i = 0; i < 10; ++i) {
      std::vector<Vector3d> s;
      for (const Vector3d& p : io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd").points)
        if (p.allFinite() && p.norm() > 0.5) s.push_back(p);
      scans.push_back(s);
    }
  }
  NdtMap mapWithout(int left_out) const {
    MapOptions o;
    o.resolution = 0.2;
    o.scan.max_range = 30;
    NdtMap map(o);
    for (int i = 0; i < 10; ++i) {
      if (i == left_out) continue;
      std::vector<Vector3d> world;
      for (const Vector3d& p : scans[i]) world.push_back(poses[i] * p);
      map.insertScan(world, poses[i].translation());
    }
    return map;
  }
};

const Balm& balm() {
  static const Balm b;
  return b;
}

}  // namespace

TEST(GlobalLocalization, GroundOfATiltedScanGivesUpAndHeight) {
  // A ground 1.4 m below a sensor tilted 15°, plus walls and clutter: RANSAC must take the ground.
  const Isometry3d sensor = [] {
    Isometry3d p = Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(15 * kDeg, Vector3d(1, 2, 0).normalized()).toRotationMatrix();
    p.translation() = Vector3d(0.3, -0.2, 1.4);
    return p;
  }();
  const auto world = room::sampleRoom(30000, 5, 0.005);
  std::vector<Vector3d> scan;
  for (const Vector3d& p : world) scan.push_back(sensor.inverse() * p);
  const GravityGuess g = findGround(scan, 45);
  ASSERT_TRUE(g.found);
  const Vector3d true_up = sensor.linear().transpose() * Vector3d::UnitZ();
  EXPECT_LT(std::acos(std::min(1.0, g.up.dot(true_up))) / kDeg, 0.5);
  EXPECT_NEAR(g.height, 1.4, 0.01);
  EXPECT_GT(g.inliers, 4000u);  // 2/7 of the 15,000 points it keeps (every second) are ground
  // No ground within the allowed tilt: nothing found.
  std::vector<Vector3d> wall;
  for (int i = 0; i < 1000; ++i) wall.emplace_back(2.0, 0.01 * i - 5, 0.003 * i - 1.5);
  EXPECT_FALSE(findGround(wall, 45).found);
}

TEST(GlobalLocalization, FindsAHeldOutRealScanWithoutAGuess) {
  const Balm& b = balm();
  for (const int k : {3, 7}) {
    const NdtMap map = b.mapWithout(k);
    GlobalLocalizer localizer(GlobalSearchOptions{}, RegistrationOptions{});
    const GlobalLocalizationResult r = localizer.localize(map, b.scans[k]);
    ASSERT_TRUE(r.found) << "scan " << k << ": " << r.failure;
    EXPECT_TRUE(r.gravity.found);
    EXPECT_GT(r.hypotheses, 100u);
    EXPECT_LT((r.best.pose.translation() - b.poses[k].translation()).norm(), 0.1) << k;
    EXPECT_LT(rotationErrorDeg(r.best.pose, b.poses[k]), 1.0) << k;
    EXPECT_TRUE(r.best.converged);
  }
}

TEST(GlobalLocalization, AScanOfAnotherPlaceIsNotFound) {
  const Balm& b = balm();
  const NdtMap map = b.mapWithout(-1);
  // The synthetic room seen from 1.5 m: a ground, but walls the campus does not have.
  std::vector<Vector3d> room_scan;
  for (const Vector3d& p : room::sampleRoom(40000, 3)) room_scan.push_back(p - room::kRoomSensor);
  GlobalLocalizer localizer(GlobalSearchOptions{}, RegistrationOptions{});
  const GlobalLocalizationResult r = localizer.localize(map, room_scan);
  EXPECT_FALSE(r.found) << "found at " << r.best.pose.translation().transpose();
  EXPECT_FALSE(r.failure.empty());
  // And the campus scan in the room's map.
  const NdtMap room_map = room::roomMap(0.2, 200000);
  const GlobalLocalizationResult r2 = localizer.localize(room_map, b.scans[4]);
  EXPECT_FALSE(r2.found);
}

TEST(GlobalLocalization, LocalSearchRecoversFromAWrongPrediction) {
  const Balm& b = balm();
  const int k = 6;
  const NdtMap map = b.mapWithout(k);
  Isometry3d wrong = b.poses[k];
  wrong.translation() += Vector3d(2.5, -2.0, 0);
  wrong.linear() = Eigen::AngleAxisd(50 * kDeg, Vector3d::UnitZ()) * wrong.linear();
  GlobalLocalizer localizer(GlobalSearchOptions{}, RegistrationOptions{});
  const GlobalLocalizationResult r = localizer.searchAround(map, b.scans[k], wrong, 4.0, 60);
  ASSERT_TRUE(r.found) << r.failure;
  EXPECT_LT((r.best.pose.translation() - b.poses[k].translation()).norm(), 0.1);
  EXPECT_LT(rotationErrorDeg(r.best.pose, b.poses[k]), 1.0);
}

// Issue #38: the search's poses were all built (and stored twice) before scoring: a recovery
// radius of 100 m on a 0.1 m grid took 2.1 GB and ended in bad_alloc. They are now counted,
// indexed and streamed; a grid past kMaxSearchPoses is not run, saying which options shrink it.
TEST(GlobalLocalization, SearchPosesAreCountedAndStreamedNotStored) {
  for (const double step : {0.1, 0.3, 2.0})
    for (const double radius : {0.0, 0.25, 2.0, 4.0, 7.3})
      for (const double yaw : {0.0, 29.0, 60.0}) {
        GlobalSearchOptions o;
        o.position_step = step;
        // The grid of the search before #38, built pose by pose.
        const int cells = int(std::floor(radius / step));
        const int yaws = int(std::floor(yaw / o.yaw_step_deg));
        size_t brute = 0;
        for (int i = -cells; i <= cells; ++i)
          for (int j = -cells; j <= cells; ++j)
            if (std::hypot(i, j) * step <= radius + 1e-9) brute += size_t(2 * yaws + 1);
        EXPECT_EQ(searchAroundPoses(o, radius, yaw), brute) << step << " " << radius << " " << yaw;
      }
  const Balm& b = balm();
  const int k = 6;
  const NdtMap map = b.mapWithout(k);
  Isometry3d wrong = b.poses[k];
  wrong.translation() += Vector3d(1.5, -1.0, 0);
  // The best few are kept per thread and merged: any thread count finds the same pose.
  RegistrationOptions one_thread;
  one_thread.threads = 1;
  GlobalSearchOptions fine;
  fine.position_step = 0.5;
  GlobalLocalizer one(fine, one_thread), all(fine, RegistrationOptions{});
  const GlobalLocalizationResult a = one.searchAround(map, b.scans[k], wrong, 3.0, 60);
  const GlobalLocalizationResult c = all.searchAround(map, b.scans[k], wrong, 3.0, 60);
  ASSERT_TRUE(a.found) << a.failure;
  EXPECT_EQ(a.hypotheses, searchAroundPoses(fine, 3.0, 60));
  EXPECT_EQ(c.hypotheses, a.hypotheses);
  EXPECT_TRUE(c.best.pose.isApprox(a.best.pose, 1e-9));
  EXPECT_LT((a.best.pose.translation() - b.poses[k].translation()).norm(), 0.1);
  // 1000 m on the 2 m grid, ±180°: about 10 million poses, refused at once.
  ASSERT_GT(searchAroundPoses(GlobalSearchOptions{}, 1000, 180), kMaxSearchPoses);
  const GlobalLocalizationResult huge = all.searchAround(map, b.scans[k], wrong, 1000, 180);
  EXPECT_FALSE(huge.found);
  EXPECT_EQ(huge.hypotheses, 0u);
  EXPECT_NE(huge.failure.find("raise position_step"), std::string::npos) << huge.failure;
}

TEST(GlobalLocalization, BadOptionsAreRejected) {
  GlobalSearchOptions o;
  o.scoring_level_factor = 3;  // not a level
  EXPECT_THROW(GlobalLocalizer(o, RegistrationOptions{}), std::invalid_argument);
  o = GlobalSearchOptions{};
  o.position_step = 0;
  EXPECT_THROW(GlobalLocalizer(o, RegistrationOptions{}), std::invalid_argument);
  o = GlobalSearchOptions{};
  o.ambiguity_ratio = 1.5;
  EXPECT_THROW(GlobalLocalizer(o, RegistrationOptions{}), std::invalid_argument);
  GlobalLocalizer localizer(GlobalSearchOptions{}, RegistrationOptions{});
  const GlobalLocalizationResult empty = localizer.localize(NdtMap(), balm().scans[0]);
  EXPECT_FALSE(empty.found);
  EXPECT_NE(empty.failure.find("no ground"), std::string::npos) << empty.failure;
  EXPECT_THROW(localizer.localize(room::roomMap(0.2, 20000), {Vector3d(NAN, 0, 0)}),
               std::invalid_argument);
}
