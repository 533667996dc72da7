// OnlineMapper: the shipped BALM scans, moved by known motions, mapped without their poses and
// checked against those poses (a lidar-inertial estimate, independent of this code).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <random>

#include "ndtom/map/rigid_move.h"
#include "ndtom/online/online_mapper.h"
#include "ndtom_eval/map_similarity.h"
#include "ndtom_eval/trajectory_error.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "support/map_equality.h"

using namespace ndtom;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
constexpr int kScans = 10;

// The shipped scans 0-9 were taken by a sensor at rest (4 cm apart). Each is moved here by a
// known motion M_i, as if the sensor had been at P_i·M_i: its points become M_i⁻¹·p. The
// motions drive 0.9 m a scan and turn 6° to 65° a scan, varying, so constant velocity
// mispredicts the turns by up to 55°. The answer, in the mapper's frame (its first pose is the
// identity): P_0⁻¹·P_i·M_i, up to the reference's own error.
struct Balm {
  std::vector<std::vector<Vector3d>> scans;  // sensor frame, moved
  std::vector<Isometry3d> truth;             // in the frame of scan 0
  std::vector<double> times;
  Balm() {
    std::vector<Isometry3d> poses;
    for (const auto& p : io::readPoseFile(kBalm + "/poses.txt")) poses.push_back(p.pose);
    std::ifstream times_file(kBalm + "/times.txt");
    for (double t; times_file >> t;) times.push_back(t);
    Isometry3d motion = Isometry3d::Identity();
    const double turns_deg[kScans] = {0, 6, 10, 65, 12, 6, 20, 8, 25, 10};
    for (int i = 0; i < kScans; ++i) {
      if (i > 0) {
        motion.translate(Vector3d(0.9, 0.05, 0.0));
        motion.rotate(Eigen::AngleAxisd(turns_deg[i] * M_PI / 180, Vector3d::UnitZ()));
      }
      truth.push_back(poses[0].inverse() * poses[size_t(i)] * motion);
      const auto cloud = io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd");
      std::vector<Vector3d> moved;
      for (const Vector3d& p : cloud.points) moved.push_back(motion.inverse() * p);
      scans.push_back(moved);
    }
  }
};

const Balm& balm() {
  static const Balm b;
  return b;
}

OnlineMapperOptions options(int threads = 1) {
  OnlineMapperOptions o;
  o.map.resolution = 0.2;
  o.map.scan.max_range = 30;
  o.threads = threads;
  return o;
}

struct MappedRun {
  std::vector<OnlineStep> steps;
  NdtMap map;
};

MappedRun mapWithoutPoses(const OnlineMapperOptions& o) {
  const Balm& b = balm();
  OnlineMapper mapper(o);  // starts at the identity: its own frame
  MappedRun run;
  for (int i = 0; i < kScans; ++i)
    run.steps.push_back(mapper.process(b.scans[size_t(i)], Vector3d::Zero(), b.times[size_t(i)]));
  run.map = mapper.takeMap();
  return run;
}

const MappedRun& singleThreadRun() {
  static const MappedRun r = mapWithoutPoses(options());
  return r;
}

double angleDeg(const Isometry3d& a, const Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180 / M_PI;
}

}  // namespace

TEST(OnlineMapper, FollowsMovingScansWithoutTheirPoses) {
  const MappedRun& run = singleThreadRun();
  std::vector<Vector3d> estimate, reference;
  for (int i = 0; i < kScans; ++i) {
    const OnlineStep& s = run.steps[size_t(i)];
    EXPECT_NE(s.outcome, OnlineOutcome::Lost) << i << ": " << s.registration.failure;
    EXPECT_TRUE(s.inserted) << i;
    // Each pose on its own: within 5 cm and 0.5° (the reference's rotations differ from what
    // P2D and D2D both find by up to 0.3°).
    EXPECT_LT((s.pose.translation() - balm().truth[size_t(i)].translation()).norm(), 0.05) << i;
    EXPECT_LT(angleDeg(s.pose, balm().truth[size_t(i)]), 0.5) << i;
    estimate.push_back(s.pose.translation());
    reference.push_back(balm().truth[size_t(i)].translation());
  }
  EXPECT_EQ(run.steps[0].outcome, OnlineOutcome::First);
  const TrajectoryError e = alignedTrajectoryError(estimate, reference);
  EXPECT_GT(e.length, 7.0);
  EXPECT_LT(e.rmse, 0.03);
  // A mapper that stood still would be far off: the check can fail.
  const TrajectoryError still =
      alignedTrajectoryError(std::vector<Vector3d>(kScans, Vector3d::Zero()), reference);
  EXPECT_GT(still.rmse, 1.0);
}

// The map is the map of the scans inserted at the poses the mapper reports, bit for bit: what
// ndtom-map --poses does with ndtom-slam's trajectory.
TEST(OnlineMapper, ItsMapIsTheScansInsertedAtItsPoses) {
  const MappedRun& run = singleThreadRun();
  NdtMap rebuilt(options().map);
  for (int i = 0; i < kScans; ++i) {
    const Isometry3d& pose = run.steps[size_t(i)].pose;
    std::vector<Vector3d> world;
    for (const Vector3d& p : balm().scans[size_t(i)]) world.push_back(pose * p);
    rebuilt.insertScan(world, pose * Vector3d::Zero());
  }
  ndtom::testing::expectBitIdentical(run.map, rebuilt);
  // And it is close to the map at the reference poses: most Gaussians agree.
  NdtMap reference(options().map);
  for (int i = 0; i < kScans; ++i) {
    const Isometry3d& pose = balm().truth[size_t(i)];
    std::vector<Vector3d> world;
    for (const Vector3d& p : balm().scans[size_t(i)]) world.push_back(pose * p);
    reference.insertScan(world, pose.translation());
  }
  EXPECT_GT(mapSimilarity(gaussianSetOf(run.map.coarsened(8)), gaussianSetOf(reference.coarsened(8))), 0.7);
}

TEST(OnlineMapper, SameMapAndPosesForOneAndTwoThreads) {
  const MappedRun& one = singleThreadRun();
  const MappedRun two = mapWithoutPoses(options(2));
  ASSERT_EQ(one.steps.size(), two.steps.size());
  for (size_t i = 0; i < one.steps.size(); ++i)
    EXPECT_TRUE(one.steps[i].pose.matrix() == two.steps[i].pose.matrix()) << i;
  EXPECT_EQ(one.map.numCells(), two.map.numCells());
  EXPECT_EQ(mapSimilarity(gaussianSetOf(one.map), gaussianSetOf(two.map)), 1.0);
}

TEST(OnlineMapper, AScanNothingPlacesIsLostAndLeavesTheMap) {
  const Balm& b = balm();
  OnlineMapper mapper(options());
  mapper.process(b.scans[0], Vector3d::Zero(), b.times[0]);
  mapper.process(b.scans[1], Vector3d::Zero(), b.times[1]);
  const uint64_t revision = mapper.map().revision();
  // Random points in a 100 m box, 500 m away: no pose the mapper can reach fits them.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Vector3d> nonsense;
  for (int i = 0; i < 20000; ++i) nonsense.emplace_back(500 + u(rng), u(rng), u(rng) * 0.1);
  const OnlineStep lost = mapper.process(nonsense, Vector3d::Zero(), b.times[2]);
  EXPECT_EQ(lost.outcome, OnlineOutcome::Lost);
  EXPECT_FALSE(lost.inserted);
  EXPECT_FALSE(lost.registration.failure.empty());
  EXPECT_TRUE(lost.pose.isApprox(lost.prediction));
  EXPECT_EQ(mapper.map().revision(), revision);
  // An empty scan is lost too, and the next real scan is placed again.
  const OnlineStep empty = mapper.process({}, Vector3d::Zero(), b.times[3]);
  EXPECT_EQ(empty.outcome, OnlineOutcome::Lost);
  EXPECT_EQ(mapper.map().revision(), revision);
  const OnlineStep back = mapper.process(b.scans[4], Vector3d::Zero(), b.times[4]);
  EXPECT_NE(back.outcome, OnlineOutcome::Lost) << back.registration.failure;
  EXPECT_LT((back.pose.translation() - b.truth[4].translation()).norm(), 0.05);
}

TEST(OnlineMapper, NonFinitePointsAreSkippedAndCounted) {
  const Balm& b = balm();
  OnlineMapper mapper(options());
  mapper.process(b.scans[0], Vector3d::Zero(), b.times[0]);
  std::vector<Vector3d> scan = b.scans[1];
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < scan.size(); i += 10) scan[i] = Vector3d(nan, 1, std::numeric_limits<double>::infinity());
  const OnlineStep s = mapper.process(scan, Vector3d::Zero(), b.times[1]);
  EXPECT_NE(s.outcome, OnlineOutcome::Lost) << s.registration.failure;
  EXPECT_GT(s.insertion.rejected(), scan.size() / 10 - 1);
  EXPECT_TRUE(s.pose.matrix().allFinite());
}

TEST(OnlineMapper, TimeGoingBackwardsIsRefused) {
  const Balm& b = balm();
  OnlineMapper mapper(options());
  mapper.process(b.scans[0], Vector3d::Zero(), 10.0);
  const uint64_t revision = mapper.map().revision();
  EXPECT_THROW(mapper.process(b.scans[1], Vector3d::Zero(), 9.0), std::invalid_argument);
  EXPECT_THROW(mapper.process(b.scans[1], Vector3d::Zero(), std::nan("")), std::invalid_argument);
  EXPECT_EQ(mapper.map().revision(), revision);
}

TEST(OnlineMapper, BadOptionsNameTheOption) {
  for (const auto& [change, name] :
       std::vector<std::pair<std::function<void(OnlineMapperOptions&)>, std::string>>{
           {[](OnlineMapperOptions& o) { o.target_radius = 0; }, "target_radius"},
           {[](OnlineMapperOptions& o) { o.placement.recovery_yaw_deg = 200; }, "recovery_yaw_deg"},
           {[](OnlineMapperOptions& o) { o.placement.weak_direction_sigma = -1; }, "weak_direction_sigma"},
           {[](OnlineMapperOptions& o) { o.threads = 0; }, "threads"},
           {[](OnlineMapperOptions& o) { o.map.resolution = -1; }, "resolution"}}) {
    OnlineMapperOptions o = options();
    change(o);
    try {
      OnlineMapper mapper(o);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// A loop closure corrects the live map: the map moved rigidly (movedMap) and handed back with
// the same frame change; tracking goes on in the moved frame, where the poses are the
// reference moved likewise. Without the frame change the last pose stays behind and the
// scans after it are not placed where the moved map has them.
TEST(OnlineMapper, TrackingGoesOnInAMapMovedWithItsFrame) {
  const Balm& b = balm();
  Isometry3d change = Isometry3d::Identity();
  change.translate(Vector3d(25.0, -10.0, 0.3));
  change.rotate(Eigen::AngleAxisd(1.6, Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.02, Vector3d::UnitX()));
  for (const bool move_frame : {true, false}) {
    OnlineMapper mapper(options());
    for (int i = 0; i < 5; ++i)
      mapper.process(b.scans[size_t(i)], Vector3d::Zero(), b.times[size_t(i)]);
    mapper.replaceMap(movedMap(mapper.map(), change),
                      move_frame ? change : Isometry3d::Identity());
    size_t placed_as_moved = 0;
    for (int i = 5; i < (move_frame ? kScans : 6); ++i) {
      const OnlineStep s = mapper.process(b.scans[size_t(i)], Vector3d::Zero(), b.times[size_t(i)]);
      const Isometry3d expected = change * b.truth[size_t(i)];
      const bool near = s.outcome != OnlineOutcome::Lost &&
                        (s.pose.translation() - expected.translation()).norm() < 0.05 &&
                        angleDeg(s.pose, expected) < 0.5;
      if (move_frame) {
        EXPECT_TRUE(near) << i << ": " << toString(s.outcome) << ", "
                          << (s.pose.translation() - expected.translation()).norm() << " m off";
      }
      placed_as_moved += near;
    }
    if (!move_frame) {
      EXPECT_EQ(placed_as_moved, 0u);
    }
  }
  OnlineMapper mapper(options());
  Isometry3d bad = Isometry3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(mapper.replaceMap(NdtMap(options().map), bad), std::invalid_argument);
}

// Something new in front of the sensor (here: a sector of the scan pulled halfway towards it,
// into space the earlier scans saw free) makes the free-space check refuse the scan at its
// true pose. Lost and not inserted, it still keeps the pose its registration found, so the
// next prediction starts from there; a scan the map's Gaussians do not fit keeps the
// prediction (AScanNothingPlacesIsLostAndLeavesTheMap).
TEST(OnlineMapper, AScanOnlyTheFreeSpaceCheckRefusesKeepsItsRegisteredPose) {
  const Balm& b = balm();
  constexpr size_t kIntruded = 7;  // predicted 12° off: 8° after a turn of 20°
  OnlineMapper mapper(options());
  for (size_t i = 0; i < kIntruded; ++i) {
    const OnlineStep s = mapper.process(b.scans[i], Vector3d::Zero(), b.times[i]);
    ASSERT_NE(s.outcome, OnlineOutcome::Lost) << i << ": " << s.registration.failure;
  }
  std::vector<Vector3d> intruded = b.scans[kIntruded];
  size_t pulled = 0;
  for (Vector3d& p : intruded)
    if (std::abs(std::atan2(p.y(), p.x())) < 1.0 && p.norm() > 4) {
      p *= 0.5;
      ++pulled;
    }
  ASSERT_GT(pulled, intruded.size() / 10);
  const uint64_t revision = mapper.map().revision();
  const OnlineStep s = mapper.process(intruded, Vector3d::Zero(), b.times[kIntruded]);
  EXPECT_EQ(s.outcome, OnlineOutcome::Lost);
  EXPECT_FALSE(s.inserted);
  EXPECT_EQ(mapper.map().revision(), revision);
  EXPECT_TRUE(s.registration.refused_for_free_space_only) << s.registration.failure;
  EXPECT_GT(s.registration.free_fraction, options().placement.registration.max_free_fraction);
  ASSERT_TRUE(s.pose_from_refused_registration);
  const Isometry3d& truth = b.truth[kIntruded];
  EXPECT_GT(angleDeg(s.prediction, truth), 5.0);  // the prediction would not do
  EXPECT_LT((s.pose.translation() - truth.translation()).norm(), 0.05);
  EXPECT_LT(angleDeg(s.pose, truth), 0.5);
  const OnlineStep next =
      mapper.process(b.scans[kIntruded + 1], Vector3d::Zero(), b.times[kIntruded + 1]);
  EXPECT_EQ(next.outcome, OnlineOutcome::Tracked) << next.registration.failure;
  EXPECT_FALSE(next.pose_from_refused_registration);
  EXPECT_LT((next.pose.translation() - b.truth[kIntruded + 1].translation()).norm(), 0.05);
}

// The same intrusion where the prediction is right (the shipped scans moved a fixed step a
// scan straight on, so constant velocity predicts them to the sensor's own jitter of a few cm):
// the registration from the prediction ends where the prediction is, and the mapper places and
// inserts the scan although the free-space check refused it (free_space_overrule: the motion
// and the map's Gaussians agree, the map's free space is what is out of date). With the
// overrule off, or where the registration ended further from the prediction than half the
// step the prediction made (a stalled pose lies a whole step behind), it is lost, at that pose.
TEST(OnlineMapper, AScanOnlyFreeSpaceRefusesIsPlacedWhereThePredictionAgrees) {
  constexpr size_t kIntruded = 4;
  struct Case {
    double step;       // (m) between the scans, along x
    double overrule;   // free_space_overrule
    double predicted;  // (m) the odometry given for the intruded scan's step (0: none)
    bool placed;
  };
  for (const Case& c : {Case{0.9, OnlineMapperOptions().free_space_overrule, 0, true},
                        Case{0.9, 0.0, 0, false}, Case{0.1, 0.1, 0.1, true},
                        Case{0.1, 0.1, 0.02, false}}) {
    const auto readScan = [&](size_t i) {  // as if taken c.step further on each
      std::vector<Vector3d> points =
          io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd").points;
      for (Vector3d& p : points) p.x() -= c.step * double(i);
      return points;
    };
    std::vector<Vector3d> intruded = readScan(kIntruded);
    for (Vector3d& p : intruded)
      if (std::abs(std::atan2(p.y(), p.x())) < 1.6 && p.norm() > 4) p *= 0.5;
    OnlineMapperOptions o = options();
    o.free_space_overrule = c.overrule;
    OnlineMapper mapper(o);
    for (size_t i = 0; i < kIntruded; ++i) {
      const OnlineStep s = mapper.process(readScan(i), Vector3d::Zero(), balm().times[i]);
      ASSERT_NE(s.outcome, OnlineOutcome::Lost) << i << ": " << s.registration.failure;
    }
    std::optional<Isometry3d> odometry;
    if (c.predicted > 0) odometry = Isometry3d(Eigen::Translation3d(c.predicted, 0, 0));
    const uint64_t revision = mapper.map().revision();
    const OnlineStep s =
        mapper.process(intruded, Vector3d::Zero(), balm().times[kIntruded], odometry);
    const std::string name = "step " + std::to_string(c.step) + ", overrule " +
                             std::to_string(c.overrule) + ", predicted " +
                             std::to_string(c.predicted);
    EXPECT_TRUE(s.registration.refused_for_free_space_only) << name << ": "
                                                            << s.registration.failure;
    // Where the sensor was, within the jitter of a sensor at rest.
    EXPECT_LT((s.pose.translation() - Vector3d(c.step * kIntruded, 0, 0)).norm(), 0.05) << name;
    EXPECT_EQ(s.free_space_overruled, c.placed) << name;
    EXPECT_EQ(s.pose_from_refused_registration, !c.placed) << name;
    EXPECT_EQ(s.outcome, c.placed ? OnlineOutcome::Tracked : OnlineOutcome::Lost) << name;
    EXPECT_EQ(s.inserted, c.placed) << name;
    EXPECT_EQ(mapper.map().revision() != revision, c.placed) << name;
  }
}
